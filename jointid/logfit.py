"""Fitting joint logs: load a training log and an optional held-out log, fit one, predict the other.

Both faces use this: `jointid fit --csv` and the explorer's log mode fit the
same way, so their readouts and JSON agree.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .csvlog import JointLog, LogError
from .fit import FitResult, fit_joint
from .logsource import HELDOUT, TRAINING, LoadRequest, load_joint_log  # noqa: F401 (TRAINING: re-exported)
from .model import PLAIN, JointModel
from .present.documents import log_fit_document
from .solver import NonFiniteError


@dataclass(frozen=True, eq=False)
class LoadedLogs:
    """The training log, the optional held-out log, and the fit of one to the other."""

    training: JointLog
    heldout: JointLog | None
    result: FitResult

    @property
    def name(self) -> str:
        """The training file's name, e.g. for the explorer's motion list."""
        return os.path.basename(os.path.normpath(self.training.path))

    @property
    def heldout_name(self) -> str | None:
        """The held-out file's name, or None."""
        return None if self.heldout is None else os.path.basename(os.path.normpath(self.heldout.path))

    @property
    def logs(self) -> tuple[JointLog, ...]:
        """The training log, then the held-out log when there is one."""
        return (self.training,) if self.heldout is None else (self.training, self.heldout)

    def document(self) -> dict:
        """The JSON document of `jointid fit --csv ... --json`."""
        return log_fit_document(self.result, self.training, self.heldout)

    def source_lines(self) -> tuple[str, ...]:
        """What was read: 'Training log PATH: N rows ...' and the same for the held-out log."""
        roles = ("Training log", "Held-out log")
        return tuple(f"{role} {log.source_text()}" for role, log in zip(roles, self.logs))

    def notes(self) -> tuple[str, ...]:
        """The loaders' notes (ignored columns, estimated derivatives), training log first."""
        return tuple(note for log in self.logs for note in log.notes)



def fit_logs(training: JointLog, heldout: JointLog | None = None, model: JointModel = PLAIN,
             constrained: bool = False) -> LoadedLogs:
    """Fit the training log (subject to the sign rules when `constrained`) and score it on the held-out log.

    LogError when the numbers leave double precision: an estimate or an RMSE
    that overflows would otherwise be shown as if it were a result.
    """
    try:
        result = fit_joint(training.data, None if heldout is None else heldout.data, model=model,
                           constrained=constrained, heldout_is_noiseless=False)
    except NonFiniteError as error:
        raise LogError(training.path, f"cannot be fitted: {error}; rescale its columns (other units)") from None
    with np.errstate(over="ignore", invalid="ignore"):  # checked here, with the file named
        scores = ((training, result.training_rmse), (heldout, result.heldout_rmse))
    for log, rmse in scores:
        if rmse is not None and not math.isfinite(rmse):
            raise LogError(
                log.path, "its predicted torques overflow double precision; rescale its columns (other units)"
            )
    return LoadedLogs(training, heldout, result)


def load_request(
    request: LoadRequest,
    current: LoadedLogs | None = None,
    model: JointModel = PLAIN,
    constrained: bool = False,
    progress: Callable[[int, int], None] | None = None,
    cancel: Callable[[], bool] | None = None,
) -> LoadedLogs:
    """Load one log into its role beside the current other log and refit; LogError/LoadCancelled as load_log."""
    log = load_joint_log(request, progress=progress, cancel=cancel)
    if request.role == HELDOUT:
        if current is None:
            raise ValueError("a held-out log needs a training log")
        return fit_logs(current.training, log, model, constrained)
    return fit_logs(log, None if current is None else current.heldout, model, constrained)
