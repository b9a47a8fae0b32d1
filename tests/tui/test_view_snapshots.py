"""Snapshot tests of the analysis views: SVGs pinned under snapshots/test_view_snapshots/.

Regenerate on purpose with `pytest tests/tui/test_view_snapshots.py --snapshot-update`,
then render each changed SVG to PNG (`rsvg-convert -o x.png file.svg`) and look
at it before committing.
"""

from __future__ import annotations

from support.tui_support import CANONICAL_STATES, make_app
from textual.widgets import Input

WIDE = (120, 40)
COMPACT = (80, 24)
SLOW = CANONICAL_STATES["slow_0.20"]
"""Slow motion at noise 0.20: the view where precision matters most (negative inertia in many seeds)."""


def open_view(key: str):
    """A run_before that opens a view, waits for any sweep worker, and stops cursor blinking."""

    async def run_before(pilot) -> None:
        await pilot.pause()  # let the main screen take its settings before the key opens a view
        await pilot.press(key)
        await pilot.app.workers.wait_for_complete()
        await pilot.pause()
        for widget in pilot.app.screen.query(Input):
            widget.cursor_blink = False
        await pilot.pause()

    return run_before


def test_ladder_view_compact_with_its_simulations(snap_compare):
    """Slow motion at noise 0.20 at 80x24: the table fits 80 columns, and the simulation column's contradiction
    (angle-offset's torque far worse, its simulation closer) is explained under it; scrolled to show that."""

    async def run_before(pilot) -> None:
        await open_view("l")(pilot)
        pilot.app.screen.query_one("#ladder-body").scroll_end(animate=False)
        await pilot.pause()

    assert snap_compare(make_app(SLOW), terminal_size=COMPACT, run_before=run_before)


def test_sweep_view_wide(snap_compare):
    # K = 1000 (the default) from seed 7: deterministic, and the worker is awaited.
    assert snap_compare(make_app(SLOW), terminal_size=WIDE, run_before=open_view("s"))


def test_sweep_view_compact(snap_compare):
    assert snap_compare(make_app(SLOW), terminal_size=COMPACT, run_before=open_view("s"))


def test_matrix_view_wide(snap_compare):
    assert snap_compare(make_app(SLOW), terminal_size=WIDE, run_before=open_view("m"))


def test_matrix_view_compact(snap_compare):
    assert snap_compare(make_app(SLOW), terminal_size=COMPACT, run_before=open_view("m"))


def test_residual_view_wide(snap_compare):
    assert snap_compare(make_app(SLOW), terminal_size=WIDE, run_before=open_view("e"))


def test_residual_view_against_velocity_compact(snap_compare):
    async def run_before(pilot) -> None:
        await open_view("e")(pilot)
        await pilot.press("3")
        await pilot.pause()

    assert snap_compare(make_app(SLOW), terminal_size=COMPACT, run_before=run_before)


RICH_020 = CANONICAL_STATES["rich_0.20"]
"""Rich motion at noise 0.20: the design view's comparison is at the lesson's noise."""


def design_view(run: bool, criterion_key: str = ""):
    """A run_before that opens the design view and, if asked, runs a design (8 starts, seed 0) and waits for it."""

    async def run_before(pilot) -> None:
        await open_view("d")(pilot)
        if run:
            await pilot.press("g")
            await pilot.app.workers.wait_for_complete()
            await pilot.pause()
            await pilot.pause()

    return run_before


def test_design_view_before_a_run_wide(snap_compare):
    assert snap_compare(make_app(RICH_020), terminal_size=WIDE, run_before=design_view(run=False))


def test_design_view_after_a_run_wide(snap_compare):
    assert snap_compare(make_app(RICH_020), terminal_size=WIDE, run_before=design_view(run=True))


def test_design_view_before_a_run_compact(snap_compare):
    assert snap_compare(make_app(RICH_020), terminal_size=COMPACT, run_before=design_view(run=False))


def test_design_view_after_a_run_compact(snap_compare):
    assert snap_compare(make_app(RICH_020), terminal_size=COMPACT, run_before=design_view(run=True))
