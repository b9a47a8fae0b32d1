"""Every view opened at a grid of terminal sizes from 20x5 to 250x80: no exception, no readout cut mid-word.

Each view is opened and resized through 100 sizes, and opened afresh at the extreme and
threshold sizes; the main screen is also opened at every size of the grid.
What is checked on screen is what a person reads: the lines each text widget
actually renders at its size. Every word in them must be a whole word of the
text the widget shows (a word wider than the widget itself may be folded: nothing
else could show it). The 100-size grid runs by default; opening every view at every
10th column and 5th row (384 sizes) is marked `slow`.
"""

from __future__ import annotations

import asyncio
import re

import pytest
from support.tui_support import CANONICAL_STATES, make_app, time_limit
from textual.geometry import Region
from textual.widget import Widget

from jointid.synthetic.settings import Settings
from tui.screens.main import MainScreen
from tui.widgets.fitting import FittingLine
from tui.widgets.readouts import ReadoutPanel
from tui.widgets.small_plots import GuardedPlot

WIDTHS = (20, 30, 45, 69, 70, 80, 109, 120, 180, 250)
HEIGHTS = (5, 10, 16, 21, 22, 24, 32, 40, 60, 80)
GRID = [(width, height) for width in WIDTHS for height in HEIGHTS]
"""100 sizes: the extremes, the layout's thresholds (70x22, 80x24, 110x32) on both sides, and between."""
FULL_GRID = [(width, height) for width in range(20, 251, 10) for height in range(5, 81, 5)]
"""24 x 16 = 384 sizes."""

VIEWS = {
    "s": "SweepScreen", "m": "MatrixScreen", "e": "ResidualScreen", "question_mark": "HelpScreen",
    "ctrl+p": "CommandPalette", "ctrl+o": "OpenLogScreen", "ctrl+s": "ExportScreen",
}
"""Key that opens each view over the main screen, and the view's screen class."""

TEXTS = {
    "MainScreen": ("#readouts", "#status", "#known", ".chart--summary", ".chart--heading"),
    "SweepScreen": ("#sweep-title", "#sweep-table", "#sweep-summary", ".plot--heading"),
    "MatrixScreen": ("#matrix-title", "#matrix-table", "#matrix-notes", "#matrix-explanation"),
    "ResidualScreen": ("#residual-title", "#residual-summary", "#residual-note", ".plot--heading"),
}
"""The readouts and sentences of each screen whose rendered words are checked."""

BOX_DRAWING = re.compile(r"^[\u2500-\u259f\s]+$")
"""Rules, borders and bars: not words."""


def source_text(widget: Widget) -> str:
    """Everything the widget may show, as plain text (every variant of a fitting line)."""
    if isinstance(widget, ReadoutPanel):
        return "\n".join(line.plain for line in widget.lines(widget.content_region.width))
    if isinstance(widget, FittingLine):
        return "\n".join(variant.plain for variant in widget.variants)
    return str(widget.render())


def cut_words(widget: Widget) -> list[str]:
    """Words the widget renders that are not whole words of its text (nothing cut: [])."""
    region = widget.region
    if not widget.display or region.width <= 0 or region.height <= 0:
        return []
    words = set(source_text(widget).split())
    width = widget.content_region.width
    too_wide = [word for word in words if len(word) > width]
    cut = []
    for strip in widget.render_lines(Region(0, 0, region.width, region.height)):
        for word in strip.text.split():
            if word in words or BOX_DRAWING.match(word) or any(word in long for long in too_wide):
                continue
            cut.append(word)
    return cut


def check_screen(screen, size) -> None:
    """No readout of the screen shown is cut mid-word, and its charts drew or said why not."""
    for selector in TEXTS.get(type(screen).__name__, ()):
        for widget in screen.query(selector):
            assert cut_words(widget) == [], (size, type(screen).__name__, selector, cut_words(widget))
    for plot in screen.query(GuardedPlot):  # as the last paint left it
        assert plot.failure is None or plot.failure.startswith("(too small"), (size, plot.failure)


async def settle(pilot) -> None:
    """Wait for a sweep to finish (not for every worker: the open dialog's folder tree keeps one running)."""
    app = pilot.app
    sweeps = [worker for worker in app.workers if worker.group == "sweep"]
    if sweeps:  # an empty list would mean every worker
        await app.workers.wait_for_complete(sweeps)
    await pilot.pause()


async def open_view(pilot, key: str) -> None:
    app = pilot.app
    await pilot.press(key)
    await settle(pilot)
    assert type(app.screen).__name__ == VIEWS[key], (key, app.size, type(app.screen).__name__)


async def close_view(pilot) -> None:
    app = pilot.app
    for _ in range(3):
        if isinstance(app.screen, MainScreen):
            return
        await pilot.press("escape")
        await settle(pilot)
    assert isinstance(app.screen, MainScreen), type(app.screen).__name__


async def walk(settings: Settings, sizes: list[tuple[int, int]], keys=tuple(VIEWS)) -> int:
    """Open every view at every size (resize, open, check, close); the number of views opened."""
    opened = 0
    app = make_app(settings)
    async with app.run_test(size=sizes[0]) as pilot:
        await pilot.pause()
        for size in sizes:
            await pilot.resize_terminal(*size)
            check_screen(app.screen, size)
            for key in keys:
                await open_view(pilot, key)
                check_screen(app.screen, size)
                await close_view(pilot)
                opened += 1
            assert app._exception is None, size
    return opened


async def resize_each_view_through(settings: Settings, sizes: list[tuple[int, int]]) -> int:
    """Open each view once and resize it through every size, checking at each; the sizes checked."""
    checked = 0
    app = make_app(settings)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        for key in VIEWS:  # the main screen: opened at every size, below
            await open_view(pilot, key)
            for size in sizes:
                await pilot.resize_terminal(*size)  # which lets the app lay out and paint
                check_screen(app.screen, size)
                checked += 1
            await close_view(pilot)
            assert app._exception is None, key
    return checked


OPEN_AT = [(20, 5), (22, 80), (69, 21), (70, 22), (80, 24), (120, 40), (250, 80)]
"""Sizes every view is also opened at (views lay out the same whether opened or resized there;
the main screen builds its size classes when it opens, checked at every grid size below)."""


# Every view through all 100 sizes takes over a minute: `pytest -m slow` runs it; the default
# run opens every view at the extreme and threshold sizes and the main screen at all 100.
@pytest.mark.slow
@pytest.mark.parametrize("state", ["slow_0.20", "holds"])
def test_every_view_through_a_grid_of_100_sizes(state):
    """Slow motion at noise 0.20 has the widest readouts and every chart; holds (no histograms) is slow-marked."""
    with time_limit(600):
        checked = asyncio.run(resize_each_view_through(CANONICAL_STATES[state], GRID))
    assert checked == len(GRID) * len(VIEWS) == 700


def test_every_view_opened_at_the_extreme_and_threshold_sizes():
    with time_limit(600):
        assert asyncio.run(walk(CANONICAL_STATES["slow_0.20"], OPEN_AT)) == len(OPEN_AT) * len(VIEWS)


def test_the_main_screen_opened_at_every_size_of_the_grid():
    """The main screen builds its layout for the size it opens at (compact rows, too small), not only on resize."""

    async def open_at(size):
        app = make_app(CANONICAL_STATES["slow_0.20"])
        async with app.run_test(size=size) as pilot:
            await pilot.pause()
            check_screen(app.screen, size)

    with time_limit(600):
        for size in GRID:
            asyncio.run(open_at(size))


@pytest.mark.slow
def test_every_view_opened_at_every_10th_column_and_5th_row():
    """2688 openings, about a quarter of an hour."""
    with time_limit(3600):
        assert asyncio.run(walk(CANONICAL_STATES["slow_0.20"], FULL_GRID)) == len(FULL_GRID) * len(VIEWS)


def test_the_check_finds_a_word_cut_at_the_edge_and_allows_one_too_wide_to_show():
    from textual.app import App
    from textual.widgets import Static

    class Cut(App):
        CSS = "Static { width: 7; text-wrap: nowrap; text-overflow: clip; }"

        def compose(self):
            yield Static("abc defgh", id="cut")
            yield Static("wrapped words", id="wrapped", classes="wrap")
            yield Static("abcdefghijk", id="wide")

    async def main():
        app = Cut()
        async with app.run_test(size=(20, 6)) as pilot:
            await pilot.pause()
            return [cut_words(app.query_one(f"#{name}")) for name in ("cut", "wrapped", "wide")]

    cut, wrapped, wide = asyncio.run(main())
    assert cut == ["def"] and wrapped == [] and wide == []  # "wrapped" fits 7 columns exactly
