"""The lab's readouts of a fit, the precision note under each parameter, and the uncertainty text.

The labels match the lesson's lab; the command line prints these and the
explorer displays them, so the two never disagree.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..estimation.uncertainty import AT_BOUND, WELL_DETERMINED_LIMIT
from .status import CONDITION_CAVEAT, CONDITION_CAVEAT_SHORT, DEPENDENT_COLUMNS, condition_text, status_message
from .text import UNAVAILABLE, format_number

if TYPE_CHECKING:
    from ..estimation.fit import FitResult


@dataclass(frozen=True)
class Readout:
    """One labelled readout line: label with unit, value text, and the sign rule it breaks ('' if none)."""

    key: str
    label: str
    text: str
    failed_requirement: str = ""
    """The sign rule the value breaks, e.g. 'I > 0'; '' when it breaks none."""

    @property
    def sign_failure(self) -> bool:
        """True when the value breaks its term's sign rule."""
        return bool(self.failed_requirement)


def readouts(result: FitResult, linear: bool = False) -> tuple[Readout, ...]:
    """The lab's readouts for a fit in display order: rank, one per parameter, both RMSEs, motion RMS (in m/s and
    m/s² when `linear`: a log whose position is a length)."""
    estimate = result.estimate
    speed = "m/s" if linear else "rad/s"
    unit = result.model.effort.unit

    def optional(key: str, label: str, value: float | None) -> Readout:
        return Readout(key, label, UNAVAILABLE if value is None else format_number(value))

    parameters = []
    for index, parameter in enumerate(result.model.parameters):
        if estimate is None:
            parameters.append(Readout(parameter.name, parameter.readout_label, UNAVAILABLE))
            continue
        failed = parameter.requirement if parameter.name in result.sign_failures else ""
        parameters.append(Readout(parameter.name, parameter.readout_label, format_number(estimate[index]), failed))
    return (
        Readout("rank", "Regressor rank", f"{result.rank} / {result.parameter_count}"),
        *parameters,
        optional("training_rmse", f"Training RMSE ({unit})", result.training_rmse),
        optional("heldout_rmse", f"Held-out RMSE ({unit})", result.heldout_rmse),
        Readout("accel_rms", f"Acceleration RMS ({speed}²)", format_number(result.accel_rms)),
        Readout("speed_rms", f"Speed RMS ({speed})", format_number(result.speed_rms)),
    )


def readouts_text(result: FitResult, linear: bool = False) -> str:
    """Every readout on its own line, label padded, then the status sentence."""
    items = readouts(result, linear)
    width = max(28, *(len(r.label) + 1 for r in items))  # other models' labels may be longer
    lines = [
        f"{r.label:<{width}}{r.text:>12}" + (f"  fails {r.failed_requirement}" if r.sign_failure else "")
        for r in items
    ]
    return "\n".join(lines) + "\n\n" + status_message(result)


@dataclass(frozen=True)
class PrecisionNote:
    """One parameter's line: the text before the verdict, the verdict ('' for none), and the compact row's text.

    `short` is a small terminal's whole row for a parameter without a value
    (rank-deficient fits); '' when the row shows the value.
    """

    key: str
    text: str
    verdict: str = ""
    short: str = ""


@dataclass(frozen=True)
class Precision:
    """Every parameter's precision note and the closing lines (a value object: equal means no redraw)."""

    notes: tuple[PrecisionNote, ...]
    closing: tuple[tuple[str, str], ...]
    """(label, text) pairs: the condition number, its caveat, where the ± comes from."""
    compact_closing: str = ""
    """The condition number and its caveat on one line, for small terminals."""


def parameter_notes(result: FitResult) -> tuple[PrecisionNote, ...]:
    """One note per parameter: standard error and the judged verdict, or what a rank-deficient fit still
    determines."""
    uncertainty = result.uncertainty
    model = result.model
    if uncertainty is None:
        subset = result.identifiable
        reported = model.report(subset.basic_estimate)
        zero = dict(zip(model.column_names, subset.zero_columns))
        notes = []
        for index, parameter in enumerate(model.parameters):
            name, columns = parameter.name, model.columns_behind(parameter.name)
            if all(column in subset.values for column in columns):
                alone = f"{name} = {format_number(reported[index])}"
                notes.append(PrecisionNote(name, f"{alone}, determined alone", short=f"{alone} determined alone"))
            elif any(zero[column] for column in columns):
                reason = parameter.invisible_when
                notes.append(PrecisionNote(name, f"not determined: {reason}", short=f"{name} unavailable: {reason}"))
            else:
                notes.append(PrecisionNote(name, "cannot be separated from the others",
                                           short=f"{name} unavailable: not separable"))
        return tuple(notes)
    errors = uncertainty.verdict_std_error
    if errors is None:
        return tuple(PrecisionNote(name, "no standard error: N - p = 0") for name in model.names)
    return tuple(
        PrecisionNote(name, AT_BOUND) if verdict == AT_BOUND else PrecisionNote(name, f"± {format_number(error)}", verdict)
        for name, error, verdict in zip(model.names, errors, result.judgement.verdicts)
    )


def closing_lines(result: FitResult) -> tuple[tuple[str, str], ...]:
    """(label, text) pairs: the condition number, its caveat, and where the ± comes from."""
    condition = result.condition_number
    if not math.isfinite(condition):
        return (("Condition number", condition_text(condition)), ("", DEPENDENT_COLUMNS))
    lines = [("Condition number", condition_text(condition)), ("", CONDITION_CAVEAT_SHORT)]
    basis = result.uncertainty.verdict_basis if result.uncertainty is not None else None
    if basis is not None:
        lines.append(("", "± from the noise bound" if basis == "expected" else "± from the residuals"))
    return tuple(lines)


def compact_closing_line(result: FitResult) -> str:
    """The condition number and its caveat in one short line."""
    condition = result.condition_number
    if not math.isfinite(condition):
        return "Cond. number ∞: columns dependent"
    return f"Cond. number {condition:.2f}, modest ≠ accurate"


def precision(result: FitResult) -> Precision:
    """The precision notes and closing lines of a fit."""
    return Precision(parameter_notes(result), closing_lines(result), compact_closing_line(result))


def ratio_determined(result: FitResult) -> bool:
    """True when h/I is well determined (its relative error within WELL_DETERMINED_LIMIT) and better than h's and
    I's own: only then is it 'determined better than the scale they share'."""
    _, value, error = result.scale_ratio
    relative = result.uncertainty.relative_std_pct
    own = [relative[result.model.index_of(kind)] for kind in ("I", "h")]
    ratio_relative = 100 * error / abs(value) if value else math.inf
    return ratio_relative <= WELL_DETERMINED_LIMIT and all(ratio_relative < other for other in own)


NEAR_NATURAL = 1.5
"""'Near its natural frequency': the motion's dominant frequency within this factor of sqrt(h g / I)."""


def swings_near_natural_frequency(result: FitResult) -> bool:
    """True when the training motion's dominant frequency (the peak of its speed's spectrum, gaps allowed) is within
    NEAR_NATURAL of the fitted pendulum's sqrt(h g / I); False without times or a positive h g / I (a prescribed
    sine at another frequency is not a swing)."""
    import numpy as np

    from ..model.terms import G

    data, estimate, model = result.training, result.estimate, result.model
    inertia, mass_moment = estimate[model.index_of("I")], estimate[model.index_of("h")]
    if data.t is None or not model.effort.is_torque or not inertia > 0 or not mass_moment > 0:
        return False
    natural = math.sqrt(mass_moment * G / inertia)
    stride = max(1, data.count // 20_000)  # the spectrum's peak needs no more samples than that
    t, speed = data.t[::stride], data.qd[::stride] - np.mean(data.qd[::stride])
    # A spectrum evaluated at the samples' own times, so the gaps left by excluded samples need no grid.
    frequencies = natural * np.geomspace(0.1, 10.0, 241)
    power = np.abs(np.exp(-1j * np.outer(frequencies, t - t[0])) @ speed)
    dominant = float(frequencies[int(np.argmax(power))])
    return abs(math.log(dominant / natural)) <= math.log(NEAR_NATURAL)


def uncertainty_text(result: FitResult) -> str:
    """Lines of 'value ± standard error, verdict' per parameter, then the condition number.

    The verdict is the fit's judgement (a log's checks may weaken the noise's verdict), with why it is weaker.
    """
    uncertainty = result.uncertainty
    model = result.model
    lines = []
    if uncertainty is None:
        subset = result.identifiable.values
        known = ", ".join(f"{name} = {format_number(value)}" for name, value in subset.items())
        lines.append(f"{'Determined alone':<28}{known or 'none'}")
    else:
        errors = uncertainty.verdict_std_error
        basis = uncertainty.verdict_basis
        for i, parameter in enumerate(model.parameters):
            label = parameter.symbol_with_unit
            if errors is None:
                lines.append(f"{label:<17}{format_number(uncertainty.estimate[i]):>11}   no standard error")
                continue
            if uncertainty.verdicts[i] == AT_BOUND:
                lines.append(f"{label:<17}{format_number(uncertainty.estimate[i]):>11}   {AT_BOUND} (no standard error)")
                continue
            relative = uncertainty.relative_std_pct[i]
            verdict, reason = result.judgement.verdicts[i], result.judgement.reasons[i]
            why = f", {reason}" if reason else ""
            lines.append(
                # At least one space before the verdict, however wide the error is.
                f"{label:<17}{format_number(uncertainty.estimate[i]):>11} ± {format_number(errors[i]):<9} "
                f"{verdict} ({relative:.1f} %{why})"
            )
        if basis == "expected":
            lines.append(
                f"Standard errors above: expected from the noise bound {format_number(result.noise_bound, 2)} N m "
                "(uniform, variance b²/3)."
            )
        if uncertainty.residual_std_error is not None:
            free = [i for i, v in enumerate(uncertainty.verdicts or ()) if v != AT_BOUND] or range(model.size)
            from_residuals = ", ".join(f"{model.names[i]} {format_number(uncertainty.noise_std_error[i])}" for i in free)
            if uncertainty.effective_count is None:
                lines.append(f"From the residuals (N - p = {uncertainty.degrees_of_freedom}): {from_residuals}.")
            else:
                lines.append(f"From the residuals, allowing for their correlation after the low-pass (Newey-West; "
                             f"{uncertainty.row_count} samples worth about {uncertainty.effective_count:.0f} "
                             f"independent ones): {from_residuals}.")
            intervals = ", ".join(
                f"{model.names[i]} [{format_number(uncertainty.interval95[i][0])}, "
                f"{format_number(uncertainty.interval95[i][1])}]"
                for i in free
            )
            widened = uncertainty.spread is not None and bool(np.any(uncertainty.spread > 0))
            lines.append(f"95 % intervals (Student t{', on the errors widened as above' if widened else ''}): "
                         f"{intervals}.")
    ratio = result.scale_ratio
    if ratio is not None and ratio_determined(result):
        corr, value, error = ratio
        inertia, gravity = (model.terms[model.index_of(kind)].name for kind in ("I", "h"))
        unit = "1/m" if model.effort.is_torque else "rad/s²"
        swings = " (the joint swings near its natural frequency)" if swings_near_natural_frequency(result) else ""
        widened = " (widened by the analysis choices too)" if result.judged is not None and \
            result.judged.ratio_spread > 0 else ""
        lines.append(f"The acceleration and gravity columns correlate at {corr:.3f}{swings}: {gravity}/{inertia} = "
                     f"{format_number(value)} ± {format_number(error)} {unit}{widened} is determined better than "
                     "the scale they share.")
    if result.constrained and result.unconstrained_estimate is not None:
        values = ", ".join(f"{name} {format_number(value)}"
                           for name, value in zip(model.names, result.unconstrained_estimate))
        lines.append(f"Without the sign constraint the fit is {values}.")
    condition = result.condition_number
    label = "Condition number (column-scaled regressor)"
    if math.isfinite(condition):
        lines.append(f"{label} {condition_text(condition)}: {CONDITION_CAVEAT}.")
    else:
        lines.append(f"{label} {condition_text(condition)}: {DEPENDENT_COLUMNS}.")
    return "\n".join(lines)

