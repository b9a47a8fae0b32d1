"""The status sentence under a fit and its warnings, in plain words.

Both are built from a FitResult and its model's terms: labels, units and sign
rules come from the terms, so the sentences hold for any model.
"""

from __future__ import annotations

import math
import os
from typing import TYPE_CHECKING

from ..estimation.uncertainty import NOT_DETERMINED, WEAK, WELL_DETERMINED
from ..text_safety import shown_name
from .text import capitalise, format_number, join_words

if TYPE_CHECKING:
    from ..estimation.fit import FitResult

MODEST_CONDITION = 100.0
"""Below this a condition number looks harmless, which is when it most needs its caveat."""
LARGE_CONDITION = 1e6
"""Above this the columns are so nearly dependent that rounding alone disturbs the fit."""

CONDITION_CAVEAT = "a modest value does not mean the parameters are accurate"
"""Shown beside every condition number: slow motion scores about 3.78 with its inertia undetermined."""
CONDITION_CAVEAT_SHORT = "modest does not mean accurate"
"""The caveat where a side panel has room for a few words."""
DEPENDENT_COLUMNS = "the columns are linearly dependent"
"""Why the condition number is infinite."""


def accuracy_sentences(result: FitResult) -> tuple[str, ...]:
    """Plain sentences on what the fit does not determine; the status sentence ends with them."""
    if result.estimate is None:
        return subset_sentences(result)
    uncertainty = result.uncertainty
    sentences = []
    if uncertainty.residual_std_error is None:
        sentences.append(
            f"With {result.training.count} samples and {result.parameter_count} parameters there are "
            "no residual degrees of freedom, so standard errors cannot be estimated from the residuals."
        )
    if uncertainty.verdicts is None:
        return tuple(sentences)
    model = result.model
    judgement = result.judgement
    judged = dict(zip(model.names, judgement.verdicts))
    reasons = dict(zip(model.names, judgement.reasons))
    errors = dict(zip(model.names, uncertainty.verdict_std_error))
    basis = uncertainty.verdict_basis

    def listing(verdict: str) -> tuple[str, str] | None:
        names = [name for name in model.names if judged[name] == verdict]
        if not names:
            return None
        values = ", ".join(f"{name} {format_number(errors[name])}" for name in names)
        plural = "s" if len(names) > 1 else ""
        return (
            f"{join_words([model.parameter(name).label for name in names])} {'are' if plural else 'is'}",
            f"({basis} standard error{plural} {values})",
        )

    if failed := listing(NOT_DETERMINED):
        subject, detail = failed
        sentences.append(f"A unique fit is not an accurate one here: {subject} not determined {detail}.")
    if weak := listing(WEAK):
        subject, detail = weak
        sentences.append(f"{capitalise(subject)} only weakly determined {detail}.")
    # A parameter whose error a check widened, or whose verdict it weakened, says why and by how much.
    weakened = "; ".join(f"{name} ({reason})" for name, reason in reasons.items() if reason)
    if weakened:
        sentences.append(f"Less certain than their noise alone says: {weakened}.")
    return tuple(sentences)


def subset_sentences(result: FitResult) -> tuple[str, ...]:
    """What a rank-deficient fit still determines, and why the rest is free."""
    subset = result.identifiable
    model = result.model
    sentences = []
    if subset.values:
        known = join_words(
            [
                f"the {model.term(name).label} {name} = {format_number(value)} {model.term(name).unit}"
                for name, value in subset.values.items()
            ]
        )
        own = "its" if len(subset.values) == 1 else "their"
        sentences.append(f"The data still determine {known} on {own} own.")
    free = subset.undetermined
    zero = [name for name in free if subset.zero_columns[model.column_names.index(name)]]
    if zero:
        reasons = join_words(list(dict.fromkeys(model.term(name).invisible_when for name in zero)))
        subject = join_words([model.term(name).label for name in zero])
        verb = "are" if len(zero) > 1 else "is"
        sentences.append(f"{capitalise(subject)} {verb} not determined: the data have {reasons}.")
    tangled = [name for name in free if name not in zero]
    if tangled:
        subject = join_words([model.term(name).label for name in tangled])
        sentences.append(
            f"{capitalise(subject)} cannot be separated: their regressor columns are "
            "linearly dependent in these data."
        )
    return tuple(sentences)


def fit_warnings(result: FitResult) -> tuple[str, ...]:
    """Every caution about a fit, one sentence each (the accuracy ones and the conditioning)."""
    sentences = list(accuracy_sentences(result))
    condition = result.condition_number
    verdicts = result.judgement.verdicts if result.uncertainty is not None else None
    if result.estimate is None:
        sentences.insert(0, f"Rank {result.rank} of {result.parameter_count}: no unique least-squares fit.")
    elif condition > LARGE_CONDITION:
        sentences.append(
            f"The condition number {condition:.3g} is large: the columns are nearly dependent, "
            f"so small {result.model.effort.name} errors move the parameters a lot."
        )
    elif condition < MODEST_CONDITION and verdicts and any(v != WELL_DETERMINED for v in verdicts):
        sentences.append(
            f"The condition number {condition:.2f} is modest, yet not every parameter is well "
            "determined: conditioning measures how distinct the columns are, not how far each "
            "parameter's signal rises above the noise."
        )
    return tuple(sentences)


NO_HELDOUT = "No held-out data, so predictions are untested."
"""Said where a fit has nothing to predict: in its status sentence, and in a report in place of the chart."""


def status_message(result: FitResult) -> str:
    """The status sentence the lab shows under its readouts."""
    rank, total = result.rank, result.parameter_count
    if result.estimate is None:
        return " ".join(
            [
                f"Rank {rank} of {total}: no unique least-squares fit.",
                "Parameter and prediction readouts are unavailable.",
                *accuracy_sentences(result),
            ]
        )
    parts = [f"Rank {rank} of {total}: a unique least-squares fit."]
    if result.constrained:
        parts.append(constraint_sentence(result))
    if result.heldout_rmse is None:
        parts.append(NO_HELDOUT)
    else:
        # Measured held-out torques carry their own noise, which no fit can predict.
        effort = result.model.effort
        measured = ("" if result.heldout_is_noiseless
                    else f" against measured {effort.name}s, so it includes their measurement noise")
        parts.append(f"Held-out {effort.name} RMSE is {format_number(result.heldout_rmse)} {effort.unit}{measured}.")
    model = result.model
    for name in result.sign_failures:
        parameter = model.parameter(name)
        value = result.estimate[model.names.index(name)]
        parts.append(
            f"Fitted {parameter.label} {format_number(value)} {parameter.unit} "
            f"fails this joint model's requirement {parameter.requirement}."
        )
    if not result.sign_failures and not result.at_bound:  # the constraint's sentence says it already
        parts.append("Positive parameter signs alone do not establish an accurate physical model.")
    parts.extend(accuracy_sentences(result))
    return " ".join(parts)


def constraint_sentence(result: FitResult) -> str:
    """What the sign constraint did, and that correct signs are not accuracy."""
    model = result.model
    if not result.at_bound:
        return "Fitted subject to the sign rules; no bound is active, so this is the unconstrained fit."
    held = join_words([
        f"the {model.parameter(name).label} at its bound {format_number(result.estimate[model.names.index(name)])} "
        f"{model.parameter(name).unit}" for name in result.at_bound
    ])
    return f"The sign rules hold {held}; correct signs are not accuracy."


def condition_text(condition: float) -> str:
    """'1.28' or 'infinite'."""
    return f"{condition:.2f}" if math.isfinite(condition) else "infinite"


def as_sentence(text: str) -> str:
    """The text ending with a full stop."""
    return text if text.endswith(".") else f"{text}."


def log_status(logs, compact: bool = False) -> str:
    """A log fit's status sentence, the sensitivity warning, what was left out in a few words, and where the notes
    are (logfit.LoadedLogs): the notes themselves have their own view (`log_notes_text`), so they never push the
    readouts off a small screen.

    Compact (80x24): `compact_log_status`, which names parameters and leaves their errors to the readouts.
    """
    # Only log fits carry a sensitivity check: a synthetic fit need not import it.
    from .notes import left_out_brief, omitted_sentence
    from .sensitivity import sensitivity_warning

    if compact:
        return compact_log_status(logs)
    check = logs.sensitivity
    warning = () if check is None or not check.flagged else (sensitivity_warning(check, compact=compact),)
    omitted = omitted_sentence(logs)
    left = left_out_brief(logs)
    return " ".join((status_message(logs.result), *warning, *(() if omitted is None else (omitted,)),
                     *(() if left is None else (left,)), NOTES_POINTER))


NOTES_POINTER = "n: the notes (how the log was read, filtered and checked)."
"""Where a log fit's notes are, at the end of its status."""


def compact_status(result: FitResult, untested: str = "untested (no held-out data)") -> str:
    """A fit's status in about three lines of 78 columns, for a side panel that shows the values and errors: the
    rank, what the sign rules did, the parameters that fail their sign rule, and those not or weakly determined,
    by name; without a unique fit, what the data still determine and the parameters they do not (each readout
    says why)."""
    if result.estimate is None:
        return compact_subset_status(result)
    tested = (untested if result.heldout_rmse is None
              else f"held-out RMSE {format_number(result.heldout_rmse)} {result.model.effort.unit}")
    parts = [f"Rank {result.rank} of {result.parameter_count}: a unique fit, {tested}."]
    names = result.model.names
    if result.constrained:
        held = ", ".join(result.at_bound)
        parts.append(f"Sign rules: {held} held at the bound." if held else "Sign rules: no bound active.")
    parts.extend(f"Fitted {name} fails its sign rule." for name in result.sign_failures)
    verdicts = result.judgement.verdicts if result.uncertainty.verdicts is not None else None
    if verdicts is not None:
        found = [f"{', '.join(name for name, judged in zip(names, verdicts) if judged == verdict)} {words}"
                 for verdict, words in ((NOT_DETERMINED, "not determined"), (WEAK, "weak"))
                 if verdict in verdicts]
        if found:
            parts.append(f"Unique is not accurate: {'; '.join(found)}.")
    return " ".join(parts)


def compact_subset_status(result: FitResult) -> str:
    """A rank-deficient fit's status in a few words: the rank, what the data still determine, and which parameters
    they do not (the readouts beside say why, one by one)."""
    subset, model = result.identifiable, result.model
    parts = [f"Rank {result.rank} of {result.parameter_count}: no unique fit."]
    if subset.values:
        known = ", ".join(f"{name} = {format_number(value)} {model.term(name).unit}" for name, value in subset.values.items())
        parts.append(f"The data still determine {known} on {'its' if len(subset.values) == 1 else 'their'} own.")
    if subset.undetermined:
        parts.append(f"Not determined: {', '.join(subset.undetermined)}.")
    return " ".join(parts)


def compact_log_status(logs) -> str:
    """A log fit's status in about four lines of 78 columns, so 80x24 keeps every readout on screen: the rank,
    the parameters not or weakly determined and those the derivative settings move, by name (the readouts beside
    give their values and errors), what was left out, and where the notes are."""
    from .notes import left_out_brief, omitted_sentence

    result = logs.result
    if result.estimate is None:
        return f"{status_message(result)} n: notes."
    parts = [compact_status(result, untested="untested (no held-out log)")]
    check = logs.sensitivity
    if check is not None and check.flagged:
        moved = [name for name, flagged in zip(check.names, check.flags) if flagged]
        largest = max(check.worst(j)[1] for j, flagged in enumerate(check.flags) if flagged)
        parts.append(f"The derivative settings move {', '.join(moved)} (up to {largest:.1f} noise standard errors).")
    omitted = omitted_sentence(logs, compact=True)
    left = left_out_brief(logs)
    return " ".join((*parts, *(() if omitted is None else (omitted,)), *(() if left is None else (left,)),
                     "n: notes."))


def simulation_text(check, label_width: int = 28) -> str:
    """The simulation check as a readout line and a sentence (simulation.SimulationCheck; None: no unique fit)."""
    if check is None:
        return f"{'Simulation error':<{label_width}}unavailable: no unique fit to integrate."
    windows = len(check.window_errors)
    label = f"Simulation error (H = {check.horizon:g} s)"
    value = "diverged" if check.rmse is None else f"{format_number(check.rmse)} rad"
    sentence = (f"The fitted model, driven by the true torque of the validation motion and restarted from the "
                f"true state every {check.horizon:g} s, follows it to this RMS angle error; "
                f"{check.diverged_windows} of {windows} windows diverged (angle error above 1 rad) and are "
                "not averaged in.")
    if check.smoothed:
        sentence += " Coulomb friction's sign(qd) is smoothed as tanh(qd/0.01) in the simulation only."
    return f"{label:<{label_width}}{value}\n{sentence}"


def log_sources(logs) -> tuple[str, ...]:
    """What was read, one short line per log, file names only: 'test.csv: 200 rows, radians'."""
    roles = ("", "Held-out ")
    return tuple(
        f"{role}{shown_name(os.path.basename(os.path.normpath(log.path)))}: {log.read_brief or f'{log.rows} rows'}, "
        f"{log.position_unit}"
        for role, log in zip(roles, logs.logs)
    )
