"""How well the motion revealed each parameter, as short lines under the readouts.

Each parameter readout gets one line: `± standard error  verdict` for a unique
fit, or, without one, whether the data still determine the parameter alone
and why not otherwise. The condition number and its caveat close the panel.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from textual.content import Content

from jointid.fit import ZERO_COLUMN_REASONS, FitResult, format_number
from jointid.model import PARAMETER_NAMES
from jointid.uncertainty import NOT_DETERMINED, WEAK, WELL_DETERMINED

INDENT = "  "
"""Precision lines sit under their readout, indented."""

VERDICT_STYLES = {WELL_DETERMINED: "$text-success", WEAK: "$text-warning", NOT_DETERMINED: "$text-error"}
"""Theme colour of each verdict (the words carry the meaning; colour only repeats it)."""


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
    compact_closing: str = ""
    """The condition number and its caveat on one line, for small terminals."""


def parameter_notes(result: FitResult) -> tuple[PrecisionNote, ...]:
    """One note per parameter: standard error and verdict, or what a rank-deficient fit still determines."""
    uncertainty = result.uncertainty
    if uncertainty is None:
        subset = result.identifiable
        notes = []
        for index, name in enumerate(PARAMETER_NAMES):
            if name in subset.values:
                alone = f"{name} = {format_number(subset.values[name])}"
                notes.append(PrecisionNote(name, f"{alone}, determined alone", short=f"{alone} determined alone"))
            elif subset.zero_columns[index]:
                reason = ZERO_COLUMN_REASONS[name]
                notes.append(PrecisionNote(name, f"not determined: {reason}", short=f"{name} unavailable: {reason}"))
            else:
                notes.append(PrecisionNote(name, "cannot be separated from the others",
                                           short=f"{name} unavailable: not separable"))
        return tuple(notes)
    errors = uncertainty.verdict_std_error
    if errors is None:
        return tuple(PrecisionNote(name, "no standard error: N - p = 0") for name in PARAMETER_NAMES)
    return tuple(
        PrecisionNote(name, f"± {format_number(error)}", verdict)
        for name, error, verdict in zip(PARAMETER_NAMES, errors, uncertainty.verdicts)
    )


def closing_lines(result: FitResult) -> tuple[tuple[str, str], ...]:
    """(label, text) pairs: the condition number, its caveat, and where the ± comes from."""
    condition = result.condition_number
    if not math.isfinite(condition):
        return (("Condition number", "infinite"), ("", "the columns are linearly dependent"))
    # The core's caveat, shortened to fit the side panel; the help text gives it in full.
    lines = [("Condition number", f"{condition:.2f}"), ("", "modest does not mean accurate")]
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


def note_lines(precision: Precision | None, key: str, width: int) -> list[Content]:
    """The note under readout `key` (none for readouts that are not parameters)."""
    if precision is None:
        return []
    lines = []
    for note in precision.notes:
        if note.key != key:
            continue
        line = Content(INDENT + note.text)
        if note.verdict:
            line += Content("  ") + verdict_content(note.verdict)
        lines.append(line)
    return lines


def verdict_content(verdict: str) -> Content:
    """A verdict in its theme colour (the words alone carry the meaning, for NO_COLOR)."""
    return Content.from_markup(f"[{VERDICT_STYLES[verdict]}]$v[/]", v=verdict)


def closing_content(precision: Precision | None, label_width: int) -> list[Content]:
    """The closing lines: labelled values as the readouts have them, notes indented and dim."""
    if precision is None:
        return []
    return [
        Content(label.ljust(label_width) + text) if label
        # dim, not $text-muted: that variable has alpha, which showed as plain text here.
        else Content.from_markup("[dim]$t[/]", t=INDENT + text)
        for label, text in precision.closing
    ]
