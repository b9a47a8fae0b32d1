"""Torque charts: measured or true torques as dots, fitted predictions as a line."""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from textual.app import ComposeResult
from textual.color import Color
from textual.containers import Vertical
from textual.content import Content

from jointid.fit import FitResult, format_number

from .fitting import FittingLine
from .torque_plot import TorquePlot

DOT_MARKER = "●"
"""Marker of measured/true torques; differs in shape from the line so it reads without colour."""
LINE_MARKER = "braille"
"""Marker of the fitted prediction line: fine braille dots. Half blocks ("hd") build in
about 2 ms a chart instead of 4 ms but draw a line as thick as the data; readability wins."""
LEGEND_LINE = "⠒⠒"
"""How the fitted line looks in the legend."""


@dataclass(frozen=True, eq=False)
class ChartData:
    """What one torque chart shows; arrays have shape (N,).

    Attributes:
        titles: Chart title, longest first; the widest that fits is shown.
        t: Sample times (s).
        dots: Measured or true torques (N m).
        line: Fitted predictions (N m), or None without a unique fit.
        dots_label: Legend text for the dots.
        line_label: Legend text for the line.
        summaries: The one-line text summary, longest first, for people who cannot see the chart.
        x_label: The x axis label (a log without times is plotted against sample index).
    """

    titles: tuple[str, ...]
    t: np.ndarray
    dots: np.ndarray
    line: np.ndarray | None
    dots_label: str
    line_label: str
    summaries: tuple[str, ...]
    x_label: str = "Time (s)"

    def same_as(self, other: ChartData | None) -> bool:
        """True when other would draw exactly the same chart (arrays compared by value)."""
        if other is None or (self.titles, self.summaries, self.x_label) != (
            other.titles, other.summaries, other.x_label
        ):
            return False
        if (self.line is None) != (other.line is None):
            return False
        pairs = [(self.t, other.t), (self.dots, other.dots)]
        if self.line is not None:
            pairs.append((self.line, other.line))
        return all(np.array_equal(a, b) for a, b in pairs)

    def key(self) -> tuple:
        """A hashable value that is equal exactly when two charts draw the same figure."""
        line = None if self.line is None else self.line.tobytes()
        return (self.titles, self.x_label, self.t.tobytes(), self.dots.tobytes(), line)

    def headings(self) -> tuple[Content, ...]:
        """Title and legend on one line, longest first (the legend never hides data here)."""
        line_label = None if self.line is None else self.line_label
        return heading_variants(self.titles, self.dots_label, line_label)


@lru_cache(maxsize=64)
def heading_variants(titles: tuple[str, ...], dots_label: str, line_label: str | None) -> tuple[Content, ...]:
    """A chart's heading for each title, with the legend; parsed once (a few per chart, reused every press)."""
    markup = "[b]$title[/b]  [$primary]$dot[/] $dots"
    if line_label is not None:
        markup += "  [$accent]$line[/] $line_label"
    return tuple(
        Content.from_markup(markup, title=title, dot=DOT_MARKER, dots=dots_label,
                            line=LEGEND_LINE, line_label=line_label or "")
        for title in titles
    )


def _chart(result: FitResult, data, predictions, rmse, titles, dots_label, line_label,
           what: str) -> ChartData:
    low, high = (format_number(float(f(data.tau)), 2) for f in (np.min, np.max))
    if predictions is None:
        unavailable = f"rank {result.rank} of 3, predictions unavailable"
        summaries = (
            f"{data.count} {what} torques (dots), {low} to {high} N m; no {line_label} line: "
            f"{unavailable}.",
            f"{data.count} {what}, {low} to {high} N m; {unavailable}",
            f"{dots_label} {low}..{high} N m; no predictions",
        )
        titles = (f"{titles[0]}: predictions unavailable", *titles)
    else:
        error = format_number(rmse)
        summaries = (
            f"{data.count} {what} torques (dots), {low} to {high} N m; "
            f"{line_label} line, RMSE {error} N m.",
            f"{data.count} {what}, {low} to {high} N m; RMSE {error} N m",
            f"{dots_label} {low}..{high} N m; RMSE {error}",
        )
    return ChartData(titles=titles, t=data.time_axis, dots=data.tau, line=predictions,
                     dots_label=dots_label, line_label=line_label, summaries=summaries)


def training_chart(result: FitResult) -> ChartData:
    """The 'Fit the training torques' chart for a fit."""
    return _chart(result, result.training, result.training_predictions, result.training_rmse,
                  ("Fit the training torques", "Training fit", "Training"), "measured", "fitted", "measured")


def heldout_chart(result: FitResult) -> ChartData:
    """The 'Predict a different motion' chart: the noiseless held-out torques and predictions."""
    return _chart(result, result.heldout, result.heldout_predictions, result.heldout_rmse,
                  ("Predict a different motion", "Held-out prediction", "Held-out"), "true", "predicted",
                  "noiseless held-out")


class TorqueChart(Vertical):
    """A plotext torque chart over time with a heading (legend) and a one-line summary."""

    DEFAULT_CSS = """
    TorqueChart {
        height: 1fr;
        min-height: 6;
    }
    TorqueChart > TorquePlot {
        height: 1fr;
    }
    TorqueChart > .chart--summary {
        color: $text-muted;
    }
    """

    def __init__(self, *, id: str | None = None) -> None:
        """Create an empty chart.

        Args:
            id: Widget id.
        """
        super().__init__(id=id)
        self.data: ChartData | None = None
        self.draws = 0  # how many times the plot was rebuilt; tests check redraws are skipped

    def compose(self) -> ComposeResult:
        """The heading with the legend, the plot, and the summary line."""
        yield FittingLine(classes="chart--heading")
        yield TorquePlot()
        yield FittingLine(classes="chart--summary")

    @property
    def summary(self) -> str:
        """The summary text as displayed at the current width."""
        return self.query_one(".chart--summary", FittingLine).shown.plain

    def show(self, data: ChartData) -> None:
        """Display new chart data; skip the redraw when nothing visible changed."""
        if data.same_as(self.data):
            return
        self.data = data
        self.query_one(".chart--heading", FittingLine).show(data.headings())
        self.query_one(".chart--summary", FittingLine).show(tuple(map(Content, data.summaries)))
        self.draws += 1
        self.query_one(TorquePlot).show_figure(data.key(), self._draw)

    def _theme_rgb(self, variable: str) -> tuple[int, int, int]:
        # plotext needs concrete colours; take them from the theme so they follow it.
        return Color.parse(self.app.theme_variables[variable]).rgb

    def _draw(self, plt) -> None:
        """Set up the plotext figure for the current data (the plot calls this when it builds)."""
        draw_torque_chart(plt, self.data, line_rgb=self._theme_rgb("accent"), dots_rgb=self._theme_rgb("primary"))


def draw_torque_chart(plt, data: ChartData, line_rgb: tuple[int, int, int], dots_rgb: tuple[int, int, int]) -> None:
    """Set up a plotext figure for a torque chart.

    Every setting the chart uses is set here each time, so the figure does not
    depend on what the plot drew before and plotext's `clear_figure` (a deep
    copy of its defaults, half a millisecond) is not needed; a test checks it.
    """
    plt.clear_data()
    plt.xlabel(data.x_label)
    plt.ylabel("Torque (N m)")
    # No top or right frame line: a row saved is a row of data at 80x24.
    plt.xaxes(True, False)
    plt.yaxes(True, False)
    plt.xlim(float(data.t[0]), float(data.t[-1]))
    low, high = float(data.dots.min()), float(data.dots.max())
    if data.line is not None:
        low, high = min(low, float(data.line.min())), max(high, float(data.line.max()))
    # A flat series (holds) would give plotext a zero-height axis; pad it.
    pad = max(0.05 * (high - low), 0.1)
    plt.ylim(low - pad, high + pad)
    # The line goes first so the dots, the data the fit must explain, are drawn on top.
    if data.line is not None:
        plt.plot(data.t, data.line, marker=LINE_MARKER, color=line_rgb)
    plt.scatter(data.t, data.dots, marker=DOT_MARKER, color=dots_rgb)
