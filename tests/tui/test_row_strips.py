"""Readouts, status, chart captions (tui/widgets/rows.py) and charts repaint only changed rows, as Textual renders them."""

from __future__ import annotations

import asyncio

import pytest
from support.tui_support import make_app
from textual.geometry import Region
from textual.strip import Strip
from textual.visual import Visual

from tui.widgets.fitting import FittingLine
from tui.widgets.readouts import ReadoutPanel
from tui.widgets.rows import RowStrips
from tui.widgets.torque_plot import TorquePlot

KEYS = [("#noise", ["right", "right", "shift+right", "left", "shift+left"]),
        ("#samples", ["right", "shift+right", "left"]),
        ("#seed", ["right", "right", "left"]),
        ("#motion", ["2", "3", "1"]),
        ("#noise", ["shift+right"] * 6),
        ("#motion", ["r"])]
"""Presses that change every readout, the status sentence (wrapped) and the chart summaries."""


def textual_rows(widget: RowStrips) -> list[Strip]:
    """The widget's rows as Textual's Widget renders its `render()`: the whole text at once, blank below."""
    width, height = widget.size
    strips = Visual.to_strips(widget, widget.render(), width, height, widget.visual_style)
    blank = Strip.blank(width, widget.visual_style.rich_style)
    return [strips[y] if y < len(strips) else blank for y in range(height)]


def painted_rows(widget: RowStrips) -> list[Strip]:
    """What the widget's styled rows are now, from the rows kept since earlier frames where not repainted."""
    return widget.render_lines(Region(0, 0, *widget.outer_size))


def freshly_styled_rows(widget: RowStrips) -> list[Strip]:
    """The same rows styled from scratch (nothing kept from earlier frames)."""
    widget._styles_cache.clear()
    return widget.render_lines(Region(0, 0, *widget.outer_size))


@pytest.mark.parametrize("size", [(120, 40), (80, 24)])
def test_every_press_paints_the_rows_textual_would(size):
    checked = []

    async def main():
        app = make_app()
        async with app.run_test(size=size) as pilot:
            await pilot.pause()
            widgets = [*app.screen.query(ReadoutPanel), *app.screen.query(FittingLine)]
            assert len(widgets) == 6  # readouts, status, two headings and two summaries
            for selector, keys in KEYS:
                app.screen.query_one(selector).focus()
                for key in keys:
                    await pilot.press(key)
                    await pilot.pause()
                    for widget in widgets:
                        if not widget.display or not widget.size.width:
                            continue
                        width, height = widget.size
                        ours = [widget.render_line(y) for y in range(height)]
                        assert ours == textual_rows(widget), (key, widget)
                        assert painted_rows(widget) == freshly_styled_rows(widget), (key, widget)
                        checked.append(widget)
                    for plot in app.screen.query(TorquePlot):  # rows kept from the last figure must still be right
                        if plot.display and plot.size.width:
                            assert painted_rows(plot) == freshly_styled_rows(plot), (key, plot)

    asyncio.run(main())
    assert any(widget.id == "status" for widget in checked)
    assert any(isinstance(widget, ReadoutPanel) for widget in checked)


def test_a_press_repaints_only_the_rows_that_changed():
    seen = {}

    async def main():
        app = make_app()
        async with app.run_test(size=(120, 40)) as pilot:
            await pilot.pause()
            panel = app.screen.query_one(ReadoutPanel)
            before = [panel.render_line(y) for y in range(panel.size.height)]
            calls = []
            refresh = panel.refresh
            panel.refresh = lambda *regions, **options: (calls.append((regions, options)), refresh(*regions, **options))[1]
            app.screen.query_one("#noise").focus()
            await pilot.press("right")  # noise 0 -> 0.01: the fitted values change, rank and RMS rows do not
            await pilot.pause()
            after = [panel.render_line(y) for y in range(panel.size.height)]
            seen["calls"], seen["height"] = calls, panel.size.height
            seen["changed"] = {y for y, (a, b) in enumerate(zip(before, after)) if a != b}

    asyncio.run(main())
    assert seen["changed"]  # the press changed some readouts
    assert len(seen["calls"]) == 1
    regions, options = seen["calls"][0]
    assert options == {}  # no relayout
    assert {region.y for region in regions} == seen["changed"]  # exactly those rows, nothing else
    assert all(region.height == 1 for region in regions)
    assert len(seen["changed"]) < seen["height"]


def test_a_line_with_rows_to_fill_picks_a_variant_at_no_width():
    """The storm resized the status to no width: wrapping a variant to choose one raised ValueError there."""
    from textual.content import Content

    line = FittingLine(min_lines=3)
    line.show((Content("a long sentence " * 4), Content("short")))
    assert line.pick(0).plain == "short" and line.pick(-1).plain == "short"
    assert line.pick(40).plain.startswith("a long")  # two rows of 40: fits in three
