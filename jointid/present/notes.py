"""The notes a fit of logs carries: how each log was read, timed, differentiated and low-passed, in words."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from ..estimation.low_pass import ATTENUATION_DB, FILTER_NAME, FLATNESS
from .text import ordinal

if TYPE_CHECKING:
    from ..estimation.low_pass import ParallelFilter
    from ..studies.log_fit import LoadedLogs


def log_notes(logs: LoadedLogs) -> tuple[str, ...]:
    """The loaders' notes (ignored columns, timing, estimated derivatives) and the filter's, training log first."""
    notes = list(logs.training.notes)
    if logs.filter is not None:
        notes.append(f"{logs.training.path}: {low_pass_note(logs.filter)}")
    if logs.heldout is not None:
        notes.extend(logs.heldout.notes)
    return tuple(notes)


def short_log_notes(logs: LoadedLogs) -> tuple[str, ...]:
    """The notes in a few words each (files without folders), for a narrow status line."""
    notes = list(logs.training.short_notes)
    if logs.filter is not None:
        notes.append(f"{os.path.basename(logs.training.path)}: {low_pass_short_note(logs.filter)}")
    if logs.heldout is not None:
        notes.extend(logs.heldout.short_notes)
    return tuple(notes)


def low_pass_short_note(low_pass: ParallelFilter) -> str:
    """The low-pass in a few words, for a narrow status line."""
    if not low_pass.active:
        return "not low-passed"
    kept = "" if low_pass.decimation == 1 else f", every {ordinal(low_pass.decimation)} sample kept"
    return f"torque and regressor low-passed at {low_pass.cutoff:.3g} Hz{kept}"


def low_pass_note(low_pass: ParallelFilter) -> str:
    """The low-pass and decimation in one sentence for a person."""
    if not low_pass.active:
        return f"torque and regressor columns not low-passed: {low_pass.reason}."
    design = low_pass.design
    kept = "" if low_pass.decimation == 1 else f", then every {ordinal(low_pass.decimation)} sample kept"
    return (f"torque and every regressor column low-passed alike at {low_pass.cutoff:.3g} Hz (zero-phase FIR, "
            f"{FILTER_NAME}, {design.length} taps, Kaiser beta {design.beta:.3g}: flat within "
            f"{FLATNESS:.1%} below {design.passband_edge:.3g} Hz, {ATTENUATION_DB:g} dB down above "
            f"{design.stopband_edge:.3g} Hz; each end extended by {low_pass.extension} samples, reflected about "
            f"a line fitted to its last half cutoff period, so no sample is lost){kept} ({low_pass.reason}); "
            "the training RMSE is of the filtered torque.")
