"""A PlotextPlot that renders plotext's character matrix straight to strips, once per change."""

from __future__ import annotations

from collections import OrderedDict
from functools import lru_cache
from typing import Callable, Hashable

from plotext import _utility as plotext_utility
from rich.segment import Segment
from rich.style import Style
from rich.text import Text
from textual.strip import Strip
from textual_plotext import PlotextPlot

from . import plotext_speedups

plotext_speedups.install()


@lru_cache(maxsize=512)
def cell_style(foreground, style, background) -> Style:
    """The Rich style of one plotext cell, decoded from exactly the ANSI code plotext would print."""
    ansi = plotext_utility.colors_to_ansi(foreground, style, background)
    text = Text.from_ansi(f"{ansi}x{plotext_utility.ansi_end}")
    return Style.combine(span.style for span in text.spans) if text.spans else Style()


def build_matrix(plot, width: int, height: int, theme: str | None = None):
    """Lay out a set-up plotext figure at a size (and theme) and return its matrix of cells."""
    plot.plotsize(width, height)
    plot._set_size(width, height)  # as PlotextPlot.render does; see its comment
    if theme is not None:
        plot.theme(theme)
    plot._set_sizes()
    plot._build_matrix()
    return plot.monitor.matrix


class TorquePlot(PlotextPlot):
    """PlotextPlot with a cached line renderer.

    The stock widget prints the figure to an ANSI string and parses it back on
    every render, about 8 ms per chart at 120x40; a key press redraws two
    charts, so that alone would miss a 60 Hz frame. Here the figure's matrix
    of characters and colours becomes strips directly, and only when the data,
    the size or the theme changed; recent figures are kept, so stepping back or
    returning to a tour stop costs nothing.
    """

    CACHE_SIZE = 64
    """Figures kept per plot: stepping back and forth or touring revisits recent ones."""

    def __init__(self) -> None:
        """Create an empty plot."""
        super().__init__()
        self._figure_key: Hashable = None
        self._draw_figure: Callable | None = None
        self._strips: list[Strip] = []
        self._strips_key: tuple | None = None
        self._cache: OrderedDict[tuple, list[Strip]] = OrderedDict()

    def show_figure(self, key: Hashable, draw: Callable) -> None:
        """Show the figure that `draw(plt)` sets up; `key` is equal for equal figures.

        The figure is built lazily at the next paint, and reused from the cache
        when the same key, size and theme were drawn before.
        """
        self._figure_key, self._draw_figure = key, draw
        self.refresh()

    def _build_strips(self) -> list[Strip]:
        width, height = self.size
        # The theme is in the key: the figure's colours come from its variables.
        key = (width, height, self.app.theme, self._figure_key)
        if key == self._strips_key:
            return self._strips
        strips = self._cache.get(key)
        if strips is None:
            strips = self._render_figure(width, height)
            self._cache[key] = strips
            if len(self._cache) > self.CACHE_SIZE:
                self._cache.popitem(last=False)
        else:
            self._cache.move_to_end(key)
        self._strips, self._strips_key = strips, key
        return strips

    def _render_figure(self, width: int, height: int) -> list[Strip]:
        plot = self._plot
        if self._draw_figure is not None:
            self._draw_figure(plot)
        matrix = build_matrix(plot, width, height, self._get_plotext_theme_name(self.app.theme))
        strips = []
        for row in reversed(matrix.Rows):  # plotext's row 0 is the bottom line
            markers = matrix.marker[row]
            colours = list(zip(matrix.fullground[row], matrix.style[row], matrix.background[row]))
            segments, start = [], 0
            for col in range(1, len(markers) + 1):
                if col == len(markers) or colours[col] != colours[start]:
                    segments.append(Segment("".join(markers[start:col]), cell_style(*colours[start])))
                    start = col
            strips.append(Strip(segments, width))
        return strips

    def render_line(self, y: int) -> Strip:
        """One line of the figure (Textual's line API), built once per change."""
        width, height = self.size
        if width <= 0 or height <= 0:
            return Strip.blank(max(width, 0))
        strips = self._build_strips()
        return strips[y] if 0 <= y < len(strips) else Strip.blank(width)
