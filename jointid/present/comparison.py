"""The model ladder's comparison: a table row per model, BIC's choice, and what the other models show."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..estimation.uncertainty import NOT_DETERMINED
from .status import condition_text
from .text import UNAVAILABLE, format_number, join_words, text_table

if TYPE_CHECKING:
    from ..studies.ladder import Comparison, LadderRow

PREFERRED_MARK = "←"
"""Marks the row BIC prefers."""
SHIFT_IN_ERRORS = 3.0
"""A shared parameter moved by more than this many of the preferred fit's standard errors is named."""
CONDITION_RISE = 2.0
"""A condition number at least this many times the preferred model's is named."""
COMPARISON_HEADER = ["model", "terms", "rank", "train RMSE", "held RMSE", "BIC", "cond.", "worst determined"]
"""Columns of the comparison table."""
COMPACT_HEADER = ["model", "rank", "train", "held", "BIC", "cond.", "worst"]
"""The same without the terms (the model's name gives them), for 80 columns."""


def bic_text(bic: float | None) -> str:
    """BIC to two decimals, '-inf' for a perfect fit, 'unavailable' without a unique fit."""
    if bic is None:
        return UNAVAILABLE
    return "-inf" if bic == -math.inf else f"{bic:.2f}"


def comparison_rows(comparison: Comparison) -> list[list[str]]:
    """One row of text cells per model, in ladder order; BIC's choice marked."""
    preferred = comparison.preferred
    rows = []
    for row in comparison.rows:
        worst = row.worst_determined
        rows.append([
            row.model.name + (f" {PREFERRED_MARK}" if row is preferred else ""),
            ", ".join(row.model.names),
            f"{row.rank}/{row.model.size + row.offsets}",
            UNAVAILABLE if row.training_rmse is None else format_number(row.training_rmse),
            "-" if row.heldout_rmse is None else format_number(row.heldout_rmse),
            bic_text(row.bic),
            condition_text(row.condition_number),
            "-" if worst is None else f"{worst[0]} {worst[1]:.1f} %",
        ])
    return rows


def comparison_table(comparison: Comparison, compact: bool = False) -> str:
    """The ladder as an aligned text table (compact: without the terms column, about 76 columns)."""
    if compact:
        return text_table(COMPACT_HEADER, [[row[0], *row[2:]] for row in comparison_rows(comparison)])
    return text_table(COMPARISON_HEADER, comparison_rows(comparison))


def comparison_sentences(comparison: Comparison) -> tuple[str, ...]:
    """BIC's choice in a sentence, then what the simpler and the larger models show beside it."""
    preferred = comparison.preferred
    if preferred is None:
        return ("No model of the ladder gives a unique fit: the motion cannot separate their columns.",)
    sentences = [f"BIC prefers {preferred.model.name} ({', '.join(preferred.model.names)})"
                 + (" for the runs pooled" if comparison.run_preferences else "") + "."]
    if comparison.run_preferences:
        sentences.append("Each run alone prefers: " + ", ".join(
            f"{run} {name or 'none (no unique fit)'}" for run, name in comparison.run_preferences) + ".")
    for row in comparison.rows:
        if row is preferred or row.estimate is None:
            continue
        own, theirs = set(row.model.names), set(preferred.model.names)
        if own < theirs:
            sentences += _absorbed(row, preferred)
        elif own > theirs:
            sentences += _superfluous(row, preferred)
    return tuple(sentences)


def _absorbed(simpler: LadderRow, preferred: LadderRow) -> list[str]:
    """What a model without some of the preferred terms moves to make up for them."""
    errors = preferred.uncertainty.verdict_std_error if preferred.uncertainty is not None else None
    if errors is None:
        return []
    missing = [preferred.model.parameter(n).label for n in preferred.model.names if n not in simpler.model.names]
    shifts = []
    for index, name in enumerate(simpler.model.names):
        theirs = preferred.model.names.index(name)
        shift = abs(simpler.estimate[index] - preferred.estimate[theirs]) / max(errors[theirs], 1e-300)
        shifts.append((shift, name, simpler.estimate[index], preferred.estimate[theirs]))
    shift, name, value, reference = max(shifts)
    if shift <= SHIFT_IN_ERRORS:
        return []
    label = simpler.model.parameter(name).label
    ratio = f" ({value / reference:.1f}x)" if reference and value / reference > 0 else ""
    heldout = ("" if simpler.heldout_rmse is None or preferred.heldout_rmse is None else
               f", and its held-out error is {_rmse(simpler.heldout_rmse, preferred.model.effort.unit)} against "
               f"{_rmse(preferred.heldout_rmse, preferred.model.effort.unit)}")
    return [f"Without {join_words(missing)}, {simpler.model.name} moves its {label} to {format_number(value)} "
            f"against {format_number(reference)}{ratio} to absorb it{heldout}."]


def _superfluous(larger: LadderRow, preferred: LadderRow) -> list[str]:
    """What extra terms cost: a higher condition number, undetermined parameters."""
    extra = [n for n in larger.model.names if n not in preferred.model.names]
    labels = join_words([larger.model.parameter(n).label for n in extra])
    costs = []
    if larger.condition_number >= CONDITION_RISE * preferred.condition_number:
        costs.append(f"raises the condition number from {condition_text(preferred.condition_number)} "
                     f"to {condition_text(larger.condition_number)}")
    verdicts = larger.uncertainty.verdicts if larger.uncertainty is not None else None
    if verdicts is not None:
        loose = [n for n in extra if verdicts[larger.model.names.index(n)] == NOT_DETERMINED]
        if loose:
            costs.append(f"leaves {join_words(loose)} not determined")
    if not costs:
        return []
    return [f"Adding {labels} ({larger.model.name}) {join_words(costs)}."]


def _rmse(value: float | None, unit: str = "N m") -> str:
    """An RMSE with its unit, or 'unavailable'."""
    return UNAVAILABLE if value is None else f"{format_number(value)} {unit}"


def comparison_text(comparison: Comparison, heading: str) -> str:
    """`jointid compare`'s text: heading, table, then the sentences."""
    return "\n".join((heading, comparison_table(comparison), "", " ".join(comparison_sentences(comparison))))


def simulation_cell(check) -> str:
    """A model's simulation error for a table cell: '0.003949', '0.276394 (1/8 diverged)' or 'diverged'."""
    if check is None:
        return UNAVAILABLE
    windows = len(check.window_errors)
    if check.rmse is None:
        return f"diverged ({windows}/{windows})"
    suffix = f" ({check.diverged_windows}/{windows} diverged)" if check.diverged_windows else ""
    return format_number(check.rmse) + suffix


def simulation_table(comparison: Comparison, checks: dict, horizon: float) -> str:
    """Each model's simulation error (rad) beside its held-out torque error; models not yet simulated read '…';
    then a sentence for each model whose simulation looks better than its torque does (simulation_sentences)."""
    header = ["model", "held RMSE (N m)", f"simulation error, H = {horizon:g} s (rad)"]
    rows = [[row.model.name, "-" if row.heldout_rmse is None else format_number(row.heldout_rmse),
             simulation_cell(checks[row.model.name]) if row.model.name in checks else "…"]
            for row in comparison.rows]
    sentences = simulation_sentences(comparison, checks, horizon)
    return text_table(header, rows) + ("\n\n" + " ".join(sentences) if sentences else "")


def times(ratio: float) -> str:
    """A ratio in words' digits: '2,310' or '3.7' (no '2.31e+03' in a sentence)."""
    return f"{ratio:,.0f}" if ratio >= 100 else f"{ratio:.3g}"


CONTRADICTION = 10.0
"""A model whose held-out torque error is this many times the best one's yet simulates closer gets a sentence."""


def simulation_sentences(comparison: Comparison, checks: dict, horizon: float) -> tuple[str, ...]:
    """Why a model can simulate closer than the best torque predictor while predicting torque far worse: its fitted
    inertia is larger, so in each window the simulated joint moves less and stays near the true state it restarts
    from; a small simulation error of a sluggish model is not accuracy."""
    rows = [row for row in comparison.rows if row.heldout_rmse is not None and row.solution.estimate is not None
            and row.model.name in checks and checks[row.model.name] is not None
            and checks[row.model.name].rmse is not None]
    if len(rows) < 2:
        return ()
    best = min(rows, key=lambda row: row.heldout_rmse)
    best_inertia = float(best.solution.estimate[best.model.column_names.index("I")])
    sentences = []
    for row in rows:
        if row is best or row.heldout_rmse < CONTRADICTION * best.heldout_rmse:
            continue
        if checks[row.model.name].rmse >= checks[best.model.name].rmse:
            continue
        inertia = float(row.solution.estimate[row.model.column_names.index("I")])
        ratio = inertia / best_inertia if best_inertia else math.inf
        why = (f"its fitted inertia is {times(ratio)} times {best.model.name}'s, so its simulated joint barely moves "
               f"in a {horizon:g} s window and stays near the true state each window restarts from"
               if ratio > 1.5 else "its error in torque cancels over the windows it is simulated for")
        sentences.append(
            f"{row.model.name} simulates closer than {best.model.name} though its held-out torque error is "
            f"{times(row.heldout_rmse / best.heldout_rmse)} times larger: {why}. A small simulation error is not an "
            "accurate model.")
    return tuple(sentences)
