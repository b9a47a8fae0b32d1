"""The text `jointid fit` prints, for a fit and for a fit of logs: the library's `summary()` returns the same."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .readouts import readouts_text, uncertainty_text
from .text import settings_header

if TYPE_CHECKING:
    from ..estimation.fit import FitResult
    from ..studies.log_fit import LoadedLogs


def fit_summary(result: FitResult) -> str:
    """The settings' header (synthetic data), the readouts, then how well each parameter is determined."""
    header = () if result.settings is None else (settings_header(result.settings),)
    return "\n".join((*header, readouts_text(result), "", uncertainty_text(result)))


def log_notes(logs: LoadedLogs) -> tuple[str, ...]:
    """Every note of a fit of logs (see `jointid.present.notes`)."""
    from . import notes  # the low-pass's texts: a synthetic fit need not load its module

    return notes.log_notes(logs)


def log_notes_text(logs: LoadedLogs) -> str:
    """Everything a fit of logs says beyond its readouts, one paragraph each: what was read, the sensitivity
    check, what was left out, and every note (the explorer's notes view)."""
    from .sensitivity import sensitivity_text

    parts = [*logs.source_lines()]
    if logs.sensitivity is not None:
        parts.append(sensitivity_text(logs.sensitivity))
    from .notes import exclusion_text, omitted_sentence

    omitted = omitted_sentence(logs)
    if omitted is not None:
        parts.append(omitted)
    left = exclusion_text(logs)
    if left is not None:
        parts.append(left)
    parts += log_notes(logs)
    return "\n\n".join(parts)


def log_fit_summary(logs: LoadedLogs) -> str:
    """What was read, the readouts, the uncertainty, the sensitivity check, terms the residuals follow that the
    model lacks, and every note."""
    parts = [*logs.source_lines(), readouts_text(logs.result), "", uncertainty_text(logs.result, logs.unsettled)]
    if logs.sensitivity is not None:
        from .sensitivity import sensitivity_text  # only log fits carry a sensitivity check

        parts.append(sensitivity_text(logs.sensitivity))
    from .notes import exclusion_text, omitted_sentence

    omitted = omitted_sentence(logs)
    if omitted is not None:
        parts.append(omitted)
    left = exclusion_text(logs)
    if left is not None:
        parts += ["", left]
    notes = log_notes(logs)
    if notes:
        parts += ["", *(f"Note: {note}" for note in notes)]
    return "\n".join(parts)
