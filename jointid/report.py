"""Readouts of a fit as labelled text and as a JSON-ready dictionary.

The labels match the lesson's lab; the command line and the explorer both
take their readout text from here so the two never disagree.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .fit import FitResult, format_number
from .model import PARAMETER_NAMES, PARAMETER_UNITS, SIGN_REQUIREMENTS
from .uncertainty import finite_or_none

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
        **uncertainty_to_dict(result),
    }


def fit_document(result: FitResult, *, settings=None, source=None, derivatives=None, **extra) -> dict:
    """The command line's JSON object for one fit: `settings` (None for a log), `source`, `derivatives`, the fit.

    `source` is {"training": path, "heldout": path or None} for logs and None for
    synthetic data; `derivatives` says how missing qd/qdd were estimated, or None.
    """
    return {"settings": settings, "source": source, "derivatives": derivatives, **extra, **result_to_dict(result)}


def log_fit_document(result: FitResult, training, heldout=None) -> dict:
    """fit_document for a fit of CSV logs (csvlog.JointLog objects): source paths, derivatives and notes."""
    return fit_document(
        result,
        source={"training": training.path, "heldout": None if heldout is None else heldout.path},
        derivatives=None if training.derivatives is None else training.derivatives.to_dict(),
        heldout_derivatives=None if heldout is None or heldout.derivatives is None else heldout.derivatives.to_dict(),
        notes=[*training.notes, *(heldout.notes if heldout is not None else ())],
    )


def uncertainty_to_dict(result: FitResult) -> dict:
    """Standard errors, intervals, verdicts (objects keyed I, h, B; None where unavailable), conditioning, subset, warnings."""
    uncertainty = result.uncertainty
    return {
        "std_error": per_parameter(uncertainty and uncertainty.std_error),
        # The issues' schema: null, not an object of nulls, when no noise bound is known (logs).
        "expected_std_error": (
            None if result.noise_bound is None else per_parameter(uncertainty and uncertainty.expected_std_error)
        ),
        "relative_std_pct": per_parameter(uncertainty and uncertainty.relative_std_pct),
        "interval95": per_parameter(uncertainty and uncertainty.interval95),
        "verdicts": per_parameter(uncertainty and uncertainty.verdicts),
        "verdict_basis": uncertainty and uncertainty.verdict_basis,
        "condition_number": finite_or_none(result.condition_number),
        "identifiable": result.identifiable.values,
        "warnings": list(result.warnings),
    }


def per_parameter(values) -> dict:
    """JSON object keyed I, h, B from a (3,) sequence (floats, [low, high] pairs or strings); all None for None."""
    if values is None:
        return dict.fromkeys(PARAMETER_NAMES)
    return {name: _json_value(value) for name, value in zip(PARAMETER_NAMES, values)}


def _json_value(value):
    """A verdict string, a finite float, a [low, high] list, or None for inf/NaN."""
    if isinstance(value, str):
        return value
    if getattr(value, "shape", ()) != ():
        return [finite_or_none(v) for v in value]
    return finite_or_none(value)


CONDITION_CAVEAT = "a modest value does not mean the parameters are accurate"
"""Shown beside every condition number: slow motion scores about 3.78 with its inertia undetermined."""


def uncertainty_text(result: FitResult) -> str:
    """Lines of 'value ± standard error, verdict' per parameter, then the condition number."""
    uncertainty = result.uncertainty
    lines = []
    if uncertainty is None:
        subset = result.identifiable.values
        known = ", ".join(f"{name} = {format_number(value)}" for name, value in subset.items())
        lines.append(f"{'Determined alone':<28}{known or 'none'}")
    else:
        errors = uncertainty.verdict_std_error
        basis = uncertainty.verdict_basis
        for i, name in enumerate(PARAMETER_NAMES):
            label = f"{name} ({PARAMETER_UNITS[name]})"
            if errors is None:
                lines.append(f"{label:<17}{format_number(uncertainty.estimate[i]):>11}   no standard error")
                continue
            relative = uncertainty.relative_std_pct[i]
            lines.append(
                f"{label:<17}{format_number(uncertainty.estimate[i]):>11} ± {format_number(errors[i]):<10}"
                f"{uncertainty.verdicts[i]} ({relative:.1f} %)"
            )
        if basis == "expected":
            lines.append(
                f"Standard errors above: expected from the noise bound {format_number(result.noise_bound, 2)} N m "
                "(uniform, variance b²/3)."
            )
        if uncertainty.std_error is not None:
            from_residuals = ", ".join(
                f"{name} {format_number(v)}" for name, v in zip(PARAMETER_NAMES, uncertainty.std_error)
            )
            lines.append(f"From the residuals (N - p = {uncertainty.degrees_of_freedom}): {from_residuals}.")
            intervals = ", ".join(
                f"{name} [{format_number(low)}, {format_number(high)}]"
                for name, (low, high) in zip(PARAMETER_NAMES, uncertainty.interval95)
            )
            lines.append(f"95 % intervals (Student t): {intervals}.")
    condition = result.condition_number
    label = "Condition number (column-scaled regressor)"
    if math.isfinite(condition):
        lines.append(f"{label} {condition:.2f}: {CONDITION_CAVEAT}.")
    else:
        lines.append(f"{label} infinite: the columns are linearly dependent.")
    return "\n".join(lines)
