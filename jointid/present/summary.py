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


def log_checks(logs: LoadedLogs) -> tuple[list[str], str | None]:
    """What the checks of a fit of logs found, one paragraph each (the sensitivity check, terms the residuals
    follow that the model lacks), and what the fit left out (None when it kept every sample)."""
    from .notes import exclusion_text, omitted_sentence
    from .sensitivity import sensitivity_text  # only log fits carry a sensitivity check

    found = [] if logs.sensitivity is None else [sensitivity_text(logs.sensitivity, logs.result.model.effort.name)]
    omitted = omitted_sentence(logs)
    if omitted is not None:
        found.append(omitted)
    if logs.result.estimate is not None:
        found.append(RUN_TO_RUN)
    return found, exclusion_text(logs)


RUN_TO_RUN = ("Run to run: the ± and the verdicts speak of this run (its noise, widened by what the other analysis "
              "choices above move and by whether its halves agree); another run of the joint can differ by more, as "
              "the shared pendulum's runs do by up to 10 %: fit several runs together (--csv A --csv B) to judge by "
              "their scatter.")
"""What no single run can show, said under every log fit's checks (benchmarks/verdict_study.py measured it)."""


def log_notes_text(logs: LoadedLogs) -> str:
    """Everything a fit of logs says beyond its readouts, one paragraph each: what was read, the sensitivity
    check, terms the model lacks, what was left out, and every note (the explorer's notes view)."""
    found, left = log_checks(logs)
    return "\n\n".join([*logs.source_lines(), *found, *([] if left is None else [left]), *log_notes(logs)])


def log_fit_summary(logs: LoadedLogs) -> str:
    """What was read, the readouts, the uncertainty, the sensitivity check, terms the residuals follow that the
    model lacks, and every note."""
    found, left = log_checks(logs)
    parts = [*logs.source_lines(), readouts_text(logs.result, logs.training.position_unit == "metres"), "", uncertainty_text(logs.result),
             *found]
    if left is not None:
        parts += ["", left]
    notes = log_notes(logs)
    if notes:
        parts += ["", *(f"Note: {note}" for note in notes)]
    return "\n".join(parts)
