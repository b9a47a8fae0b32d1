"""Joint logs in the explorer: what is loaded, how it is fitted, and how its charts are thinned."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import Callable

import numpy as np

from jointid.csvlog import JointLog, load_log
from jointid.dataset import JointData
from jointid.derivatives import DEFAULT_ORDER, DEFAULT_WINDOW
from jointid.fit import FitResult, fit_joint, format_number
from jointid.report import log_fit_document

from .charts import ChartData

TRAINING, HELDOUT = "training", "heldout"
"""The two roles a log can be loaded in."""


@dataclass(frozen=True)
class LoadRequest:
    """Which file to load, in which role, whether its angles are in degrees, and how to differentiate it."""

    path: str
    role: str = TRAINING
    degrees: bool = False
    window: int = DEFAULT_WINDOW
    """Savitzky-Golay window, when the log lacks qd or qdd (`jointid --window`)."""
    order: int = DEFAULT_ORDER
    """Savitzky-Golay order (`jointid --order`)."""


@dataclass(frozen=True, eq=False)
class LoadedLogs:
    """The training log, the optional held-out log, and the fit of one to the other."""

    training: JointLog
    heldout: JointLog | None
    result: FitResult

    @property
    def name(self) -> str:
        """The training file's name, as the motion control shows it."""
        return os.path.basename(self.training.path)

    def document(self) -> dict:
        """The command line's JSON document for this fit (`jointid fit --csv ... --json`)."""
        return log_fit_document(self.result, self.training, self.heldout)

    def notes(self) -> tuple[str, ...]:
        """What was read, then the loader's notes (ignored columns, estimated derivatives)."""
        logs = [self.training, *([self.heldout] if self.heldout is not None else [])]
        return (*(log.source_text() for log in logs), *(note for log in logs for note in log.notes))


def fit_logs(training: JointLog, heldout: JointLog | None) -> LoadedLogs:
    """Fit the training log and score it on the held-out log's measured torques, as the CLI does."""
    result = fit_joint(training.data, None if heldout is None else heldout.data, heldout_is_noiseless=False)
    return LoadedLogs(training, heldout, result)


def load_request(
    request: LoadRequest,
    current: LoadedLogs | None,
    progress: Callable[[int, int], None] | None = None,
    cancel: Callable[[], bool] | None = None,
) -> LoadedLogs:
    """Load one file into its role beside the current other log and refit; LogError/LoadCancelled as load_log."""
    log = load_log(request.path, degrees=request.degrees, window=request.window, order=request.order,
                   progress=progress, cancel=cancel)
    if request.role == HELDOUT:
        if current is None:
            raise ValueError("a held-out log needs a training log")
        return fit_logs(current.training, log)
    return fit_logs(log, None if current is None else current.heldout)


def thin_stride(count: int, columns: int) -> int:
    """k such that every k-th of `count` samples gives at most `columns` points (1: show all)."""
    return max(1, math.ceil(count / max(columns, 1)))


def ordinal(number: int) -> str:
    """2nd, 3rd, 4th, 11th, 21st ..."""
    suffix = "th" if 10 <= number % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(number % 10, "th")
    return f"{number}{suffix}"


def log_chart(data: JointData, predictions: np.ndarray | None, rmse: float | None, columns: int,
              titles: tuple[str, ...], what: str, line_label: str) -> ChartData:
    """A chart of a log's measured torques (dots) and the fit's (line), thinned to `columns` points."""
    count = data.count
    stride = thin_stride(count, columns)
    shown = slice(None, None, stride)
    low, high = (format_number(float(f(data.tau)), 2) for f in (np.min, np.max))
    thinned = f"; every {ordinal(stride)} of {count} samples shown" if stride > 1 else ""
    thinned_short = f"; every {ordinal(stride)} shown" if stride > 1 else ""
    if predictions is None:
        ending = "no fitted line: rank below 3, predictions unavailable"
        short = "predictions unavailable"
    else:
        ending = f"{line_label} line, RMSE {format_number(rmse)} N m"
        short = f"RMSE {format_number(rmse)} N m"
    summaries = (
        f"{count} {what} torques (dots), {low} to {high} N m; {ending}{thinned}.",
        f"{count} {what}, {low} to {high} N m; {short}{thinned_short}",
        f"{low}..{high} N m; {short}",
    )
    return ChartData(
        titles=titles,
        t=data.time_axis[shown],
        dots=data.tau[shown],
        line=None if predictions is None else predictions[shown],
        dots_label="measured",
        line_label=line_label,
        summaries=summaries,
        x_label="Time (s)" if data.t is not None else "Sample index",
    )


def log_training_chart(logs: LoadedLogs, columns: int) -> ChartData:
    """The training log's measured torques with the fitted line."""
    result = logs.result
    return log_chart(result.training, result.training_predictions, result.training_rmse, columns,
                     (f"Fit the training log {logs.name}", "Fit the training log", "Training log"),
                     "measured", "fitted")


def log_heldout_chart(logs: LoadedLogs, columns: int) -> ChartData | None:
    """The held-out log's measured torques with the fit's predictions, or None without a held-out log."""
    if logs.heldout is None:
        return None
    result = logs.result
    name = os.path.basename(logs.heldout.path)
    return log_chart(result.heldout, result.heldout_predictions, result.heldout_rmse, columns,
                     (f"Predict the held-out log {name}", "Predict the held-out log", "Held-out log"),
                     "measured held-out", "predicted")
