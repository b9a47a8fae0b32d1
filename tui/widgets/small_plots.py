"""Small plotext charts for the analysis views: histograms of sweep estimates and residual scatters."""

from __future__ import annotations

import numpy as np
from textual.app import ComposeResult
from textual.containers import Vertical
from textual.content import Content
from textual_plotext import PlotextPlot

from jointid.present.charts import HistogramData, ScatterData

from .fitting import FittingLine
from .theme import theme_rgb

HISTOGRAM_BINS = 24
"""Bars per histogram: enough to show the shape, few enough for a 26-column chart."""


class SmallPlot(Vertical):
    """A plotext chart with a one-line heading; draws a histogram or a scatter and redraws on theme change."""

    DEFAULT_CSS = """
    SmallPlot {
        height: 1fr;
        min-height: 5;
    }
    SmallPlot > PlotextPlot {
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
        self.data: HistogramData | ScatterData | None = None

    def compose(self) -> ComposeResult:
        """The heading and the plot."""
        yield FittingLine(classes="plot--heading")
        yield PlotextPlot()

    def on_mount(self) -> None:
        """Redraw with the new colours whenever the theme changes."""
        self.app.theme_changed_signal.subscribe(self, lambda _theme: self._draw())

    def show(self, data: HistogramData | ScatterData | None) -> None:
        """Display new data (None clears the chart)."""
        self.data = data
        titles = data.titles if data is not None else ("",)
        self.query_one(FittingLine).show(tuple(Content.from_markup("[b]$t[/b]", t=t) for t in titles))
        self._draw()

    def _draw(self) -> None:
        if not self.is_mounted:
            return
        plot = self.query_one(PlotextPlot)
        plt = plot.plt
        plt.clear_data()
        plt.clear_figure()
        plt.xaxes(True, False)
        plt.yaxes(True, False)
        data = self.data
        if isinstance(data, HistogramData):
            self._histogram(plt, data)
        elif isinstance(data, ScatterData):
            self._scatter(plt, data)
        plot.refresh()

    def _histogram(self, plt, data: HistogramData) -> None:
        values = data.values
        # Seeds far out in the tails (slow motion's inertia) would squeeze the bulk into
        # one bar; the 0.5..99.5 % range keeps the shape visible and the marker on scale.
        low, high = np.percentile(values, [0.5, 99.5])
        low, high = min(low, data.true_value), max(high, data.true_value)
        if high - low < 1e-12:
            low, high = low - 0.5, high + 0.5
        counts, edges = np.histogram(np.clip(values, low, high), bins=HISTOGRAM_BINS, range=(low, high))
        centres = (edges[:-1] + edges[1:]) / 2
        filled = counts > 0  # plotext draws a stub even for an empty bar
        plt.bar(centres[filled], counts[filled], width=1.0, marker="sd",
                color=theme_rgb(self.app, "primary"))
        plt.vline(data.true_value, color=theme_rgb(self.app, "accent"))
        # The heading names the quantity and unit, so no axis-label row is spent on it; three
        # short ticks replace plotext's long float tick labels.
        # The middle tick sits on the true value when it is clear of the ends, so the marker
        # has its number under it.
        middle = data.true_value if 0.2 <= (data.true_value - low) / (high - low) <= 0.8 else (low + high) / 2
        ticks = [float(low), float(middle), float(high)]
        plt.xticks(ticks, [f"{tick:.3g}" for tick in ticks])
        plt.xlim(float(low), float(high))

    def _scatter(self, plt, data: ScatterData) -> None:
        x_low, x_high = float(data.x.min()), float(data.x.max())
        if x_high - x_low < 1e-12:  # holds: q, qd and qdd are all zero
            x_low, x_high = x_low - 1.0, x_high + 1.0
        bound = max(float(np.abs(data.y).max()), 1e-3) * 1.1
        plt.xlim(x_low, x_high)
        plt.ylim(-bound, bound)
        plt.hline(0.0, color=theme_rgb(self.app, "foreground-muted"))
        plt.scatter(data.x, data.y, marker="●", color=theme_rgb(self.app, "primary"))
        plt.xlabel(data.x_label)
        plt.ylabel(data.y_label)
