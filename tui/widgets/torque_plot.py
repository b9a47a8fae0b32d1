"""A PlotextPlot that renders plotext's character matrix straight to strips, once per change."""

from __future__ import annotations

from collections import OrderedDict
from typing import Callable, Hashable

from rich.segment import Segment
from textual.strip import Strip
from textual_plotext import PlotextPlot

from ..third_party import adapter as third_party
from .plot_guard import TOO_SMALL, failure_text, too_small
from .rows import refresh_changed_rows


class TorquePlot(PlotextPlot):
    """PlotextPlot with a cached line renderer.

    The stock widget prints the figure to an ANSI string and parses it back on
    every render, and a key press redraws two charts. Here the figure's matrix
    of characters and colours becomes strips directly (`third_party.figure_strips`;
    the stock text when the versions differ), and only when the data, the size
    or the theme changed; recent figures are kept, so stepping back or
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
        when the same key, size and theme were drawn before. Once the plot has a
        size, the figure is built here and only the rows that differ from the
        ones on screen are repainted (the x axis, its ticks and label often stay).
        """
        shown, shown_key = self._strips, self._strips_key
        self._figure_key, self._draw_figure = key, draw
        width, height = self.size
        if shown_key is None or shown_key[:3] != (width, height, self.app.theme):
            self.refresh()
            return
        refresh_changed_rows(self, shown, self._build_strips())

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
        """The figure's lines, or one line saying why it is not drawn (a chart is never worth a crash)."""
        if too_small(width, height):
            return self._message_strips(TOO_SMALL, width)
        try:
            return self._figure_strips(width, height)
        except Exception as error:  # plotext's layout at sizes and data nobody foresaw
            self.log.error(f"chart not drawn at {width}x{height}: {error!r}")
            return self._message_strips(failure_text(error), width)

    @staticmethod
    def _message_strips(text: str, width: int) -> list[Strip]:
        return [Strip([Segment(text)]).crop_extend(0, width, None)]

    def _figure_strips(self, width: int, height: int) -> list[Strip]:
        if self._draw_figure is not None:
            self._draw_figure(self.plt)
        if third_party.active(third_party.CHART_MATRIX):
            return third_party.figure_strips(self, width, height)
        # Another plotext or textual-plotext than the adapter was written for: the stock
        # widget's own text, cut into strips (slower, but it is cached here all the same).
        console = self.app.console
        options = console.options.update_dimensions(width, height)
        lines = console.render_lines(super().render(), options, pad=True)
        return [Strip(line, width) for line in lines]

    def render_line(self, y: int) -> Strip:
        """One line of the figure (Textual's line API), built once per change."""
        width, height = self.size
        if width <= 0 or height <= 0:
            return Strip.blank(max(width, 0))
        strips = self._build_strips()
        return strips[y] if 0 <= y < len(strips) else Strip.blank(width)
