"""Snapshot tests of the explorer: SVG screenshots pinned under snapshots/test_snapshots/.

Regenerate on purpose with `pytest tests/test_snapshots.py --snapshot-update`,
then render each changed SVG to PNG (`rsvg-convert -o x.png file.svg`) and look
at it before committing.
"""

from __future__ import annotations

from textual.widgets import Input

from tui_support import CANONICAL_STATES, make_app

WIDE = (120, 40)
COMPACT = (80, 24)


def steady(pilot) -> None:
    """No blinking cursor, so two runs give the same picture."""
    for widget in pilot.app.query(Input):
        widget.cursor_blink = False


def test_default_wide(snap_compare):
    assert snap_compare(make_app(), terminal_size=WIDE, run_before=steady)


def test_default_compact(snap_compare):
    assert snap_compare(make_app(), terminal_size=COMPACT, run_before=steady)


def test_rich_noise_0_20(snap_compare):
    assert snap_compare(make_app(CANONICAL_STATES["rich_0.20"]), terminal_size=WIDE,
                        run_before=steady)


def test_slow_noise_0_20_flags_negative_inertia(snap_compare):
    assert snap_compare(make_app(CANONICAL_STATES["slow_0.20"]), terminal_size=WIDE,
                        run_before=steady)


def test_slow_noise_0_20_compact(snap_compare):
    assert snap_compare(make_app(CANONICAL_STATES["slow_0.20"]), terminal_size=COMPACT,
                        run_before=steady)


def test_holds_rank_one(snap_compare):
    assert snap_compare(make_app(CANONICAL_STATES["holds"]), terminal_size=WIDE,
                        run_before=steady)


def test_help_screen(snap_compare):
    assert snap_compare(make_app(), press=["question_mark"], terminal_size=WIDE,
                        run_before=steady)


def test_too_small_terminal(snap_compare):
    assert snap_compare(make_app(), terminal_size=(60, 18), run_before=steady)
