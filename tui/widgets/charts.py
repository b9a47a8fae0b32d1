"""Torque charts: measured or true torques as dots, fitted predictions as a line.

What a chart shows (series, titles, summaries) comes from `jointid.present.charts`;
this module draws it with plotext and adds the coloured legend.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from textual.app import ComposeResult
from textual.containers import Vertical
from textual.content import Content

from jointid.present.charts import ChartData, axis_ticks

from .fitting import FittingLine
from .theme import theme_rgb
from .torque_plot import TorquePlot

DOT_MARKER = "●"
"""Marker of measured/true torques; differs in shape from the line so it reads without colour."""
LINE_MARKER = "braille"
"""Marker of the fitted prediction line: fine braille dots. Half blocks ("hd") build in
about 2 ms a chart instead of 4 ms but draw a line as thick as the data; readability wins."""
LEGEND_LINE = "⠒⠒"
"""How the fitted line looks in the legend."""
MUTED = 0.5
"""How far the dots a fit left out and the shading fade into the background: Textual's '-muted' colours, which
the legend uses, are the same colours at half strength."""
Y_LABEL_WIDTH = 5
"""Torque tick labels are padded to this width ('-10.0' fits), so the plot keeps its place as values change."""
SHADE_MARKER = "░"
"""Fill of the stretches left out for an outside torque: light, so dots and line stay readable over it."""


def chart_headings(data: ChartData) -> tuple[Content, ...]:
    """Title and legend on one line, longest first (the legend never hides data here)."""
    line_label = None if data.line is None else data.line_label
    return heading_variants(data.titles, data.dots_label, line_label, data.left_out is not None, bool(data.shaded))


@lru_cache(maxsize=64)
def heading_variants(titles: tuple[str, ...], dots_label: str, line_label: str | None,
                     left_out: bool = False, shaded: bool = False) -> tuple[Content, ...]:
    """A chart's heading for each title, with the legend; parsed once (a few per chart, reused every press)."""
    markup = "[b]$title[/b]  [$primary]$dot[/] $dots"
    if line_label is not None:
        markup += "  [$accent]$line[/] $line_label"
    if left_out:
        markup += "  [$primary-muted]$dot[/] left out"
    if shaded:
        markup += "  [$warning-muted]$shade[/] outside torque"
    values = dict(dot=DOT_MARKER, dots=dots_label, line=LEGEND_LINE, line_label=line_label or "", shade=SHADE_MARKER)
    variants = [Content.from_markup(markup, title=title, **values) for title in titles]
    if left_out:  # a narrow chart keeps the kept/left-out/pushed key and drops the line's (it is plainly a line)
        short = "[b]$title[/b] [$primary]$dot[/]kept [$primary-muted]$dot[/]out" + (
            " [$warning-muted]$shade[/]push" if shaded else "")
        variants.append(Content.from_markup(short, title=titles[-1], **values))
    return tuple(variants)


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
        # The children by position, as compose yields them: three queries cost 0.1 ms a press.
        heading, plot, summary = self.children
        heading.show(chart_headings(data))
        summary.show(tuple(map(Content, data.summaries)))
        self.draws += 1
        plot.show_figure(data.key(), self._draw)

    def _draw(self, plt) -> None:
        """Set up the plotext figure for the current data (the plot calls this when it builds)."""
        app = self.app
        width, height = self.children[1].size  # the plot's own size: the tick count follows it
        draw_torque_chart(plt, self.data, line_rgb=theme_rgb(app, "accent"), dots_rgb=theme_rgb(app, "primary"),
                          faint_rgb=theme_rgb(app, "primary", MUTED), shade_rgb=theme_rgb(app, "warning", MUTED),
                          size=(width, height))


def draw_torque_chart(plt, data: ChartData, line_rgb: tuple[int, int, int], dots_rgb: tuple[int, int, int],
                      faint_rgb: tuple[int, int, int] = (96, 96, 96),
                      shade_rgb: tuple[int, int, int] = (128, 96, 32), size: tuple[int, int] | None = None) -> None:
    """Set up a plotext figure for a torque chart.

    Every setting the chart uses is set here each time, so the figure does not
    depend on what the plot drew before and plotext's `clear_figure` (a deep
    copy of its defaults, half a millisecond) is not needed; a test checks it.
    """
    plt.clear_data()
    plt.xlabel(data.x_label)
    plt.ylabel(data.y_label)
    # No top or right frame line: a row saved is a row of data at 80x24.
    plt.xaxes(True, False)
    plt.yaxes(True, False)
    plt.xlim(float(data.t[0]), float(data.t[-1]))
    # The kept samples set the torque axis; a push's dots and the line through it are clipped to its edges.
    kept = slice(None) if data.left_out is None or data.left_out.all() else ~data.left_out
    low, high = float(data.dots[kept].min()), float(data.dots[kept].max())
    if data.line is not None:
        low, high = min(low, float(data.line[kept].min())), max(high, float(data.line[kept].max()))
    # A flat series (holds) would give plotext a zero-height axis; pad it.
    pad = max(0.05 * (high - low), 0.1)
    plt.ylim(low - pad, high + pad)
    if size is not None:  # round ticks at even steps (plotext's own split the range evenly: 5.02, 4.51, 3.48 ...)
        width, height = size
        ticks, labels = axis_ticks(low - pad, high + pad, max(2, (height - 2) // 2))
        # Labels of one width, so the plot does not shift sideways when new data need a longer one ('-0.5').
        plt.yticks(ticks, [label.rjust(Y_LABEL_WIDTH) for label in labels])
        plt.xticks(*axis_ticks(float(data.t[0]), float(data.t[-1]), max(2, width // 8)))
    # Shading first, the line next, so the dots, the data the fit must explain, are drawn on top.
    for start, end in data.shaded:
        plt.rectangle([start, end], [low - pad, high + pad], marker=SHADE_MARKER, color=shade_rgb, fill=True)
    if data.line is not None:
        plt.plot(data.t, np.clip(data.line, low - pad, high + pad), marker=LINE_MARKER, color=line_rgb)
    if data.left_out is None:
        plt.scatter(data.t, data.dots, marker=DOT_MARKER, color=dots_rgb)
        return
    dots = np.clip(data.dots, low - pad, high + pad)
    for chosen, colour in ((data.left_out, faint_rgb), (~data.left_out, dots_rgb)):
        if chosen.any():
            plt.scatter(data.t[chosen], dots[chosen], marker=DOT_MARKER, color=colour)
