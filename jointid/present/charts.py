"""What every chart shows: the series, titles, axis labels and a one-line summary for each.

A chart's summary gives its content in words (range, error, what was thinned)
for anyone who cannot see the chart; titles and summaries come longest first,
so a narrow terminal shows the widest that fits.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .text import format_number, ordinal

if TYPE_CHECKING:
    from ..estimation.fit import FitResult
    from ..studies.log_fit import LoadedLogs
    from ..estimation.residuals import ResidualData
    from ..samples import JointData
    from ..studies.sweep import SweepResult


@dataclass(frozen=True, eq=False)
class ChartData:
    """What one torque chart shows; arrays have shape (N,).

    Attributes:
        titles: Chart title, longest first; the widest that fits is shown.
        t: Sample times (s), or sample indices for a log without times.
        dots: Measured or true torques (N m).
        line: Fitted predictions (N m), or None without a unique fit.
        dots_label: Legend text for the dots.
        line_label: Legend text for the line.
        summaries: The one-line text summary, longest first.
        x_label: The x axis label.
        left_out: (N,) True for the dots the fit left out (drawn faint), or None when it used them all.
        shaded: (start, end) times shaded as left out for an outside torque (a push, or by hand).
    """

    titles: tuple[str, ...]
    t: np.ndarray
    dots: np.ndarray
    line: np.ndarray | None
    dots_label: str
    line_label: str
    summaries: tuple[str, ...]
    x_label: str = "Time (s)"
    left_out: np.ndarray | None = None
    shaded: tuple[tuple[float, float], ...] = ()
    y_label: str = "Torque (N m)"
    """The effort axis's label: 'Torque (N m)', or 'Voltage (V)' for a voltage log."""

    def same_as(self, other: ChartData | None) -> bool:
        """True when other would draw exactly the same chart (arrays compared by value)."""
        if other is None or (self.titles, self.summaries, self.x_label, self.y_label) != (
            other.titles, other.summaries, other.x_label, other.y_label
        ):
            return False
        if (self.line is None) != (other.line is None):
            return False
        pairs = [(self.t, other.t), (self.dots, other.dots)]
        if self.line is not None:
            pairs.append((self.line, other.line))
        if (self.left_out is None) != (other.left_out is None) or self.shaded != other.shaded:
            return False
        if self.left_out is not None:
            pairs.append((self.left_out, other.left_out))
        return all(np.array_equal(a, b) for a, b in pairs)

    def key(self) -> tuple:
        """A hashable value that is equal exactly when two charts draw the same figure."""
        line = None if self.line is None else self.line.tobytes()
        left_out = None if self.left_out is None else self.left_out.tobytes()
        return (self.titles, self.x_label, self.y_label, self.t.tobytes(), self.dots.tobytes(), line, left_out, self.shaded)


NICE_STEPS = (1.0, 2.0, 2.5, 5.0, 10.0)
"""Tick steps per decade: evenly spaced ticks that read as round numbers."""


def axis_ticks(low: float, high: float, target: int) -> tuple[tuple[float, ...], tuple[str, ...]]:
    """About `target` evenly spaced round ticks within [low, high], and their labels with as few decimals as the
    step needs and no negative zero ('-0.0' read as a value below zero)."""
    span = high - low
    if not (span > 0 and math.isfinite(span)) or target < 1:
        return (), ()
    raw = span / max(target, 1)
    decade = 10.0 ** math.floor(math.log10(raw))
    step = next(decade * m for m in NICE_STEPS if decade * m >= raw)
    first = math.ceil(low / step - 1e-9)
    ticks = tuple(k * step for k in range(first, math.floor(high / step + 1e-9) + 1))
    decimals = max(0, -math.floor(math.log10(step) + 1e-9)) + (1 if step / decade % 1 else 0)
    labels = tuple(format_number(0.0 if abs(tick) < step / 2 else tick, decimals) for tick in ticks)
    return ticks, labels


def thin_stride(count: int, columns: int) -> int:
    """k such that every k-th of `count` samples gives at most `columns` points (1: show all)."""
    return max(1, math.ceil(count / max(columns, 1)))


def torque_chart(result: FitResult, data: JointData, predictions: np.ndarray | None, rmse: float | None, *,
                 titles: tuple[str, ...], what: str, dots_label: str, line_label: str,
                 columns: int | None = None) -> ChartData:
    """Torques as dots and the fit as a line, thinned to at most `columns` points when given."""
    count = data.count
    stride = 1 if columns is None else thin_stride(count, columns)
    shown = slice(None, None, stride)
    effort = result.model.effort
    unit, efforts = effort.unit, f"{effort.name}s"
    low, high = (format_number(float(f(data.tau)), 2) for f in (np.min, np.max))
    thinned = f"; every {ordinal(stride)} of {count} samples shown" if stride > 1 else ""
    thinned_short = f"; every {ordinal(stride)} shown" if stride > 1 else ""
    if predictions is None:
        unavailable = f"rank {result.rank} of {result.parameter_count}, predictions unavailable"
        summaries = (
            f"{count} {what} {efforts} (dots), {low} to {high} {unit}; no {line_label} line: {unavailable}{thinned}.",
            f"{count} {what}, {low} to {high} {unit}; {unavailable}{thinned_short}",
            f"{dots_label} {low}..{high} {unit}; no predictions",
        )
        titles = (f"{titles[0]}: predictions unavailable", *titles)
    else:
        error = format_number(rmse)
        summaries = (
            f"{count} {what} {efforts} (dots), {low} to {high} {unit}; {line_label} line, RMSE {error} {unit}"
            f"{thinned}.",
            f"{count} {what}, {low} to {high} {unit}; RMSE {error} {unit}{thinned_short}",
            # Narrow charts: a thinned one says so before its RMSE, which the readouts give as well.
            *((f"{dots_label} {low}..{high} {unit}; RMSE {error}; 1 in {stride}",
               f"{dots_label} {low}..{high} {unit}; 1 in {stride} shown") if stride > 1 else ()),
            f"{dots_label} {low}..{high} {unit}; RMSE {error}",
        )
    return ChartData(
        titles=titles,
        t=data.time_axis[shown],
        dots=data.tau[shown],
        line=None if predictions is None else predictions[shown],
        dots_label=dots_label,
        line_label=line_label,
        summaries=summaries,
        x_label="Time (s)" if data.t is not None else "Sample index",
        y_label=effort.label,
    )


def training_chart(result: FitResult, *, log_name: str | None = None, columns: int | None = None) -> ChartData:
    """'Fit the training torques' (or '... the training log NAME'): measured torques and the fitted line."""
    if log_name is None:
        titles = ("Fit the training torques", "Training fit", "Training")
    else:
        titles = (f"Fit the training log {log_name}", "Fit the training log", "Training log")
    return torque_chart(result, result.training, result.training_predictions, result.training_rmse,
                        titles=titles, what="measured", dots_label="measured", line_label="fitted",
                        columns=columns)


def log_training_chart(logs: LoadedLogs, *, columns: int | None = None) -> ChartData:
    """A training log's chart: every filtered sample as a dot, the ones the fit left out (standstill, outside
    torques) faint, the fit's line over all of them, and the stretches of outside torques within the log shaded,
    so a user sees what was left out and how the torque there departs from the joint's. The torque axis spans
    the kept samples: a push's torque may run off it (it is drawn at the edge)."""
    result, left = logs.result, logs.exclusions
    chart = training_chart(result, log_name=logs.name, columns=columns)
    if left is None or left.regressor is None or bool(left.kept.all()):
        return chart
    count = len(left.torque)
    stride = 1 if columns is None else thin_stride(count, columns)
    shown = slice(None, None, stride)
    line = None if result.estimate is None else (left.regressor @ result.column_estimate)[shown]
    offset = float(left.times[0] - left.since[0])  # the notes' times are from the log's start, the axis the log's
    shaded = tuple((start + offset, end + offset) for start, end in left.within)
    omitted = int(count - left.kept.sum())
    low, high = (format_number(float(f(left.torque)), 2) for f in (np.min, np.max))
    effort = result.model.effort
    rmse = "no fitted line" if line is None else f"RMSE {format_number(result.training_rmse)} {effort.unit}"
    error = rmse if line is None else f"{rmse} on the kept"
    where = ", ".join(f"{start:.2f}-{end:.2f}" for start, end in shaded)
    pushes = f"; shaded: outside torque at {where} s" if shaded else ""
    thinned = f"; every {ordinal(stride)} of {count} samples shown" if stride > 1 else ""
    summaries = (
        f"{count} filtered {effort.name}s (dots), {low} to {high} {effort.unit}, {omitted} left out (faint); "
        f"{error}{pushes}"
        f"{thinned}.",
        f"{omitted} of {count} left out (faint); {rmse}{pushes}",
        f"{omitted} of {count} left out (faint); {rmse}{'; pushes shaded' if shaded else ''}",
        f"{omitted} of {count} left out (faint){'; pushes shaded' if shaded else ''}",
        f"{omitted}/{count} left out{'; pushes shaded' if shaded else ''}",
    )
    return ChartData(titles=chart.titles, t=left.times[shown], dots=left.torque[shown], line=line,
                     dots_label="measured", line_label="fitted", summaries=summaries, x_label=chart.x_label,
                     left_out=~left.kept[shown], shaded=shaded, y_label=chart.y_label)


def heldout_chart(result: FitResult, *, log_name: str | None = None,
                  columns: int | None = None) -> ChartData | None:
    """'Predict a different motion' (or '... the held-out log NAME'), or None without held-out data."""
    if result.heldout is None:
        return None
    if log_name is None:
        titles = ("Predict a different motion", "Held-out prediction", "Held-out")
    else:
        titles = (f"Predict the held-out log {log_name}", "Predict the held-out log", "Held-out log")
    truth = result.heldout_is_noiseless
    return torque_chart(result, result.heldout, result.heldout_predictions, result.heldout_rmse,
                        titles=titles, what="noiseless held-out" if truth else "measured held-out",
                        dots_label="true" if truth else "measured", line_label="predicted", columns=columns)


@dataclass(frozen=True, eq=False)
class HistogramData:
    """One quantity's per-seed values with its true value; `values` has shape (K,)."""

    titles: tuple[str, ...]
    """Heading, longest first; the widest that fits is shown."""
    values: np.ndarray
    true_value: float
    marker_label: str = ""
    """What the vertical marker line shows, for the heading's legend: 'true 0.8'."""


TRUE_MARKER = "│"
"""The histograms' vertical marker of the true value, as drawn and as the legend shows it."""


def sweep_histograms(sweep: SweepResult) -> list[HistogramData]:
    """One histogram per parameter of a full-rank sweep, with the true value marked."""
    model = sweep.model
    seeds = "1 seed" if sweep.seed_count == 1 else f"{sweep.seed_count} seeds"
    # The legend ("│ true 0.8") follows the title as the torque charts' legends do; a
    # marker at the very end ("true 0.8 at │") read as a title cut off.
    return [
        HistogramData(
            titles=(f"{parameter.symbol_with_unit}, {seeds}", parameter.symbol_with_unit, parameter.name),
            values=sweep.values(parameter.name),
            true_value=float(true),
            marker_label=f"true {true:g}",
        )
        for parameter, true in zip(model.parameters, sweep.settings.true_joint.values_for(model))
    ]


@dataclass(frozen=True, eq=False)
class ScatterData:
    """Residuals (N,) against one axis (N,), with axis titles."""

    titles: tuple[str, ...]
    """Heading, longest first; the widest that fits is shown."""
    x: np.ndarray
    y: np.ndarray
    x_label: str
    y_label: str


def residual_scatter(data: ResidualData, axis: str) -> ScatterData:
    """The scatter of training residuals against one axis ('t', 'q', 'qd' or 'qdd')."""
    # Imported here: the explorer's first frame shows no residuals.
    from ..estimation.residuals import AXIS_LABELS

    x_label = AXIS_LABELS[axis] if data.has_times or axis != "t" else "sample index"
    return ScatterData(
        titles=(f"Training residuals ({data.unit}) against {x_label}", f"Residuals against {x_label}"),
        x=data.axes[axis],
        y=data.residuals,
        x_label=x_label.capitalize(),
        y_label=f"Residual ({data.unit})",
    )


def residual_summary(data: ResidualData) -> str:
    """One text line for people who cannot see the chart: count, range and which fit."""
    low, high = (format_number(float(f(data.residuals)), 3) for f in (min, max))
    source = ("the fit" if data.unique_fit
              else "the basic solution (rank-deficient: every solution fits the same)")
    return f"{len(data.residuals)} residuals (measured - fitted) from {source}, {low} to {high} {data.unit}."
