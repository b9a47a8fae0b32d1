"""Small plotext charts for the analysis views: histograms of sweep estimates and residual scatters."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from textual.app import ComposeResult
from textual.containers import Vertical
from textual.content import Content
from textual_plotext import PlotextPlot

from jointid.present.charts import TRUE_MARKER, HistogramData, ScatterData, axis_ticks
from jointid.present.design import LinesData

from .fitting import FittingLine
from .plot_guard import TOO_SMALL, failure_text, too_small
from .theme import theme_rgb

HISTOGRAM_BINS = 24
"""Bars per histogram: enough to show the shape, few enough for a 26-column chart."""
DEGENERATE_SPAN = 1e-9
"""A histogram range narrower than this, relative to its values' size, is widened (one value, or noise 0)."""


@dataclass(frozen=True, eq=False)
class HistogramBars:
    """A histogram ready to draw: counts (B,) of the bins between edges (B + 1,) over [low, high]."""

    counts: np.ndarray
    edges: np.ndarray
    low: float
    high: float


def histogram_bars(values: np.ndarray, true_value: float, bins: int = HISTOGRAM_BINS) -> HistogramBars | None:
    """Bin the finite values over a range that shows the bulk and the true value; None when none is finite.

    The range is never empty (one value, or every seed giving the same value, is
    centred in a range as wide as the value's size), so every bar has a width.
    """
    values = values[np.isfinite(values)]
    if values.size == 0:
        return None
    # Seeds far out in the tails (slow motion's inertia) would squeeze the bulk into
    # one bar; the 0.5..99.5 % range keeps the shape visible and the marker on scale.
    low, high = (float(v) for v in np.percentile(values, [0.5, 99.5]))
    low, high = min(low, true_value), max(high, true_value)
    scale = max(1.0, abs(low), abs(high))
    if high - low <= DEGENERATE_SPAN * scale:
        middle = (low + high) / 2
        low, high = middle - 0.5 * scale, middle + 0.5 * scale
    counts, edges = np.histogram(np.clip(values, low, high), bins=bins, range=(low, high))
    return HistogramBars(counts, edges, low, high)


def at_least_three_ticks(low: float, high: float, target: int) -> tuple[tuple[float, ...], tuple[str, ...]]:
    """`axis_ticks`, asking for more when a round step leaves fewer than three inside the range (±0.97 at a step
    of 1 had only 0)."""
    for wanted in range(target, target + 8):
        ticks, labels = axis_ticks(low, high, wanted)
        if len(ticks) >= 3:
            break
    return ticks, labels


COUNT_LABEL_WIDTH = 6
"""Histogram count labels are padded to this width: the explorer's largest sweep, 100000 seeds in one bar."""


def tick_labels(ticks: list[float]) -> list[str]:
    """Three significant digits, or as many more as it takes for different ticks to read differently.

    One seed's histogram spans a few thousandths around its value, where three
    digits labelled all three ticks '0.8'.
    """
    for digits in range(3, 16):
        labels = [f"{tick:.{digits}g}" for tick in ticks]
        if len(set(labels)) == len(set(ticks)):
            break
    return labels


class GuardedPlot(PlotextPlot):
    """A PlotextPlot that shows a line of text instead of a chart too small to draw or one that fails."""

    def __init__(self) -> None:
        """Create an empty plot."""
        super().__init__()
        self.failure: str | None = None
        """The text shown instead of the chart at the last render, or None when the chart was drawn."""
        self._setup_failure: str | None = None

    def draw(self, setup: Callable) -> None:
        """Set up the figure afresh with `setup(plt)` and repaint; an error in it shows as a line of text."""
        plt = self.plt
        plt.clear_data()
        plt.clear_figure()
        try:
            setup(plt)
        except Exception as error:  # odd data nobody foresaw: never a crash for a chart
            self.log.error(f"chart not set up: {error!r}")
            self._setup_failure = failure_text(error)
        else:
            self._setup_failure = None
        self.refresh()

    def render(self):
        """The chart, or why it is not shown."""
        width, height = self.size
        self.failure = TOO_SMALL if too_small(width, height) else self._setup_failure
        if self.failure is not None:
            return Content(self.failure)
        try:
            return super().render()
        except Exception as error:  # plotext's layout at sizes and data nobody foresaw
            self.log.error(f"chart not drawn at {width}x{height}: {error!r}")
            self.failure = failure_text(error)
            return Content(self.failure)


class SmallPlot(Vertical):
    """A plotext chart with a one-line heading; draws a histogram or a scatter and redraws on theme change."""

    DEFAULT_CSS = """
    SmallPlot {
        height: 1fr;
        min-height: 5;
    }
    SmallPlot > GuardedPlot {
        height: 1fr;
    }
    SmallPlot > .plot--heading {
        padding: 0 1;
    }
    """

    def __init__(self, *, id: str | None = None, classes: str | None = None) -> None:
        """Create an empty chart.

        Args:
            id: Widget id.
            classes: CSS classes.
        """
        super().__init__(id=id, classes=classes)
        self.data: HistogramData | ScatterData | LinesData | None = None

    def compose(self) -> ComposeResult:
        """The heading and the plot."""
        yield FittingLine(classes="plot--heading")
        yield GuardedPlot()

    def on_mount(self) -> None:
        """Redraw with the new colours whenever the theme changes."""
        self.app.theme_changed_signal.subscribe(self, lambda _theme: self._draw())

    def on_resize(self) -> None:
        """Draw again for the new size: the round ticks' count follows the plot's rows and columns."""
        if self.data is not None:
            self._draw()

    def show(self, data: HistogramData | ScatterData | LinesData | None) -> None:
        """Display new data (None clears the chart)."""
        self.data = data
        widest = data.widest_titles if isinstance(data, HistogramData) and data.widest_titles else None
        self.query_one(FittingLine).show(self.headings(data), None if widest is None else self.headings(data, widest))
        self._draw()

    @staticmethod
    def headings(data: HistogramData | ScatterData | LinesData | None,
                 titles: tuple[str, ...] | None = None) -> tuple[Content, ...]:
        """Each title (the data's, or `titles`) in bold, longest first; a histogram's followed by the legend of its
        marker line."""
        if data is None:
            return (Content(""),)
        markup = "[b]$title[/b]"
        legend = data.marker_label if isinstance(data, HistogramData) else ""
        if legend:
            markup += "  [$accent]$marker[/] $legend"
        return tuple(Content.from_markup(markup, title=title, marker=TRUE_MARKER, legend=legend)
                     for title in (data.titles if titles is None else titles))

    def _draw(self) -> None:
        if self.is_mounted:
            self.query_one(GuardedPlot).draw(self._set_up)

    def _set_up(self, plt) -> None:
        plt.xaxes(True, False)
        plt.yaxes(True, False)
        data = self.data
        if isinstance(data, HistogramData):
            self._histogram(plt, data)
        elif isinstance(data, ScatterData):
            self._scatter(plt, data)
        elif isinstance(data, LinesData):
            self._lines(plt, data)

    def _histogram(self, plt, data: HistogramData) -> None:
        bars = histogram_bars(data.values, data.true_value)
        if bars is None:
            return
        low, high = bars.low, bars.high
        # Each bar is a rectangle over its own bin: plotext's bar() guesses the width from the
        # spacing of the centres it is given, a whole data unit for a single bar, which at
        # K = 1 drew a bar thousands of columns wide and filled it point by point for minutes.
        colour = theme_rgb(self.app, "primary")
        for count, left, right in zip(bars.counts, bars.edges[:-1], bars.edges[1:]):
            if count:  # plotext draws a stub even for an empty bar
                plt.rectangle([float(left), float(right)], [0, int(count)], marker="sd", color=colour, fill=True)
        plt.vline(data.true_value, color=theme_rgb(self.app, "accent"))
        # The heading names the quantity and unit, so no axis-label row is spent on it; three
        # short ticks replace plotext's long float tick labels, whole counts on the y axis.
        # The middle tick sits on the true value when it is clear of the ends, so the marker
        # has its number under it.
        middle = data.true_value if 0.2 <= (data.true_value - low) / (high - low) <= 0.8 else (low + high) / 2
        ticks = [low, float(middle), high]
        plt.xticks(ticks, tick_labels(ticks))
        plt.xlim(low, high)
        most = int(bars.counts.max())
        counts = sorted({0, most // 2, most})
        # Labels of one width, so the plot keeps its place when the seed count gains a digit (5 -> 10000).
        plt.yticks(counts, [str(count).rjust(COUNT_LABEL_WIDTH) for count in counts])
        plt.ylim(0, max(most, 1))

    def _scatter(self, plt, data: ScatterData) -> None:
        x_low, x_high = float(data.x.min()), float(data.x.max())
        if x_high - x_low < 1e-12:  # holds: q, qd and qdd are all zero
            x_low, x_high = x_low - 1.0, x_high + 1.0
        bound = max(float(np.abs(data.y).max()), 1e-3) * 1.1
        plt.xlim(x_low, x_high)
        plt.ylim(-bound, bound)
        self._round_ticks(plt, (x_low, x_high), (-bound, bound))
        plt.hline(0.0, color=theme_rgb(self.app, "foreground-muted"))
        plt.scatter(data.x, data.y, marker="●", color=theme_rgb(self.app, "primary"))
        plt.xlabel(data.x_label)
        plt.ylabel(data.y_label)

    def _round_ticks(self, plt, x_range: tuple[float, float], y_range: tuple[float, float]) -> None:
        """Round ticks at even steps, as the torque charts have: plotext's own split the range into labels such as
        0.00110, 0.00073, 0.00037 (and could print -0.0). Sized for the plot as laid out, or a few before that."""
        width, height = self.query_one(GuardedPlot).size
        y_ticks, y_labels = at_least_three_ticks(*y_range, max(2, (height - 2) // 3) if height else 5)
        x_ticks, x_labels = at_least_three_ticks(*x_range, max(2, width // 10) if width else 5)
        if y_ticks:
            plt.yticks(y_ticks, y_labels)
        if x_ticks:
            plt.xticks(x_ticks, x_labels)

    def _lines(self, plt, data: LinesData) -> None:
        colours = (theme_rgb(self.app, "primary"), theme_rgb(self.app, "accent"))
        bound = max(max(float(np.abs(values).max()) for _, values in data.lines), 1e-3) * 1.1
        plt.xlim(float(data.x[0]), float(data.x[-1]))
        plt.ylim(-bound, bound)
        self._round_ticks(plt, (float(data.x[0]), float(data.x[-1])), (-bound, bound))
        for (label, values), colour in zip(data.lines, colours):
            plt.plot(data.x, values, label=label, color=colour, marker="braille")
        plt.xlabel(data.x_label)
