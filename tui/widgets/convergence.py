"""The watch view's convergence chart: each parameter's estimate (as a share of its latest) or its relative error
over the seconds watched, one coloured line per parameter."""

from __future__ import annotations

import numpy as np
from textual.content import Content

from jointid.estimation.uncertainty import WELL_DETERMINED_LIMIT
from jointid.present.watch import ConvergenceData

from .small_plots import GuardedPlot, SmallPlot, at_least_three_ticks
from .theme import theme_rgb

LINE_COLOURS = ("primary", "accent", "success", "warning", "error", "secondary")
"""Theme colours of the parameters' lines, in the model's order (a sixth term reuses none)."""
ESTIMATE_RANGE = (0.0, 2.0)
"""Shares of the latest estimate shown: early estimates can be wild, and what matters is the approach to 1."""
ERROR_FLOOR_PCT = 0.1
"""The error chart's lowest value (%), so a nearly exact parameter does not stretch the log axis."""


class ConvergenceChart(SmallPlot):
    """A SmallPlot for ConvergenceData, its legend in the heading."""

    def show(self, data: ConvergenceData | None) -> None:
        """Display new histories unless they draw the same as those shown."""
        if data is not None and isinstance(self.data, ConvergenceData) and data.key() == self.data.key():
            return
        super().show(data)

    def headings(self, data, titles=None) -> tuple[Content, ...]:
        """Each title in bold, then each parameter's name in its line's colour."""
        if not isinstance(data, ConvergenceData):
            return super().headings(data, titles)
        legend = Content(" ").join(Content.from_markup(f"[${colour}]━ $name[/]", name=name)
                                   for (name, _, _), colour in zip(data.lines, LINE_COLOURS))
        return tuple(Content.from_markup("[b]$title[/b]  ", title=title) + legend for title in data.titles)

    def _set_up(self, plt) -> None:
        data = self.data
        if not isinstance(data, ConvergenceData):
            return super()._set_up(plt)
        plt.xaxes(True, False)
        plt.yaxes(True, False)
        if not data.lines:
            return
        ends = [float(x[-1]) for _, x, _ in data.lines]
        starts = [float(x[0]) for _, x, _ in data.lines]
        x_range = (min(starts), max(max(ends), min(starts) + 1e-3))
        plt.xlim(*x_range)
        error_kind = data.y_label.startswith("Error")
        if error_kind:  # a log axis by hand: errors fall by decades as samples come in
            lines = [(name, x, np.log10(np.maximum(y, ERROR_FLOOR_PCT))) for name, x, y in data.lines]
            high = max(float(y.max()) for _, _, y in lines)
            y_range = (np.log10(ERROR_FLOOR_PCT), max(high, np.log10(WELL_DETERMINED_LIMIT)) + 0.1)
            decades = np.arange(np.ceil(y_range[0]), np.floor(y_range[1]) + 1)
            plt.yticks(list(decades), [f"{10 ** d:g}" for d in decades])
            # The noise's limit of 'well determined': a line below it has the error that verdict needs.
            plt.hline(float(np.log10(WELL_DETERMINED_LIMIT)), color=theme_rgb(self.app, "foreground-muted"))
        else:
            lines = [(name, x, np.clip(y, *ESTIMATE_RANGE)) for name, x, y in data.lines]
            y_range = ESTIMATE_RANGE  # no line at 1: it hid the estimates that had settled there
            ticks, labels = at_least_three_ticks(*y_range, 4)
            plt.yticks(ticks, labels)
        plt.ylim(*y_range)
        width = self.query_one(GuardedPlot).size.width
        x_ticks, x_labels = at_least_three_ticks(*x_range, max(2, width // 10) if width else 5)
        plt.xticks(x_ticks, x_labels)
        for (name, x, y), colour in zip(lines, LINE_COLOURS):
            plt.plot(x, y, color=theme_rgb(self.app, colour), marker="braille")
        plt.xlabel(data.x_label)
