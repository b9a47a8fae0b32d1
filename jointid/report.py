"""Readouts of a fit as labelled text and as a JSON-ready dictionary.

The labels match the lesson's lab; the command line and the explorer both
take their readout text from here so the two never disagree.
"""

from __future__ import annotations

from dataclasses import dataclass

from .fit import FitResult, format_number
from .model import PARAMETER_NAMES, SIGN_REQUIREMENTS

UNAVAILABLE = "unavailable"
"""Readout text when the rank gives no unique fit (or no held-out data)."""


@dataclass(frozen=True)
class Readout:
    """One labelled readout line: label with unit, value text, and whether it breaks a sign check."""

    key: str
    label: str
    text: str
    sign_failure: bool = False


def readouts(result: FitResult) -> tuple[Readout, ...]:
    """The lab's eight readouts for a fit, in display order."""
    estimate = result.estimate

    def parameter(name: str, label: str) -> Readout:
        if estimate is None:
            return Readout(name, label, UNAVAILABLE)
        value = estimate[PARAMETER_NAMES.index(name)]
        return Readout(name, label, format_number(value), name in result.sign_failures)

    def optional(key: str, label: str, value: float | None) -> Readout:
        return Readout(key, label, UNAVAILABLE if value is None else format_number(value))

    return (
        Readout("rank", "Regressor rank", f"{result.rank} / {result.parameter_count}"),
        parameter("I", "Fitted inertia (kg m²)"),
        parameter("h", "Fitted mass moment (kg m)"),
        parameter("B", "Fitted damping (N m s/rad)"),
        optional("training_rmse", "Training RMSE (N m)", result.training_rmse),
        optional("heldout_rmse", "Held-out RMSE (N m)", result.heldout_rmse),
        Readout("accel_rms", "Acceleration RMS (rad/s²)", format_number(result.accel_rms)),
        Readout("speed_rms", "Speed RMS (rad/s)", format_number(result.speed_rms)),
    )


def readouts_text(result: FitResult) -> str:
    """Every readout on its own line, label padded, then the status sentence."""
    lines = [
        f"{r.label:<28}{r.text:>12}" + (f"  fails {SIGN_REQUIREMENTS[r.key]}" if r.sign_failure else "")
        for r in readouts(result)
    ]
    return "\n".join(lines) + "\n\n" + result.message


def result_to_dict(result: FitResult) -> dict:
    """The fit as plain JSON-ready values, full float precision, None where unavailable."""
    estimate = result.estimate
    return {
        "samples": result.training.count,
        "rank": result.rank,
        "estimate": None if estimate is None else dict(zip(PARAMETER_NAMES, map(float, estimate))),
        "training_rmse": result.training_rmse,
        "heldout_rmse": result.heldout_rmse,
        "accel_rms": result.accel_rms,
        "speed_rms": result.speed_rms,
        "sign_failures": list(result.sign_failures),
        "message": result.message,
    }
