"""Snapshot tests of the explorer: SVG screenshots pinned under snapshots/test_snapshots/.

Regenerate on purpose with `pytest tests/tui/test_snapshots.py --snapshot-update`,
then render each changed SVG to PNG (`rsvg-convert -o x.png file.svg`) and look
at it before committing.
"""

from __future__ import annotations

import pytest
from support.tui_support import CANONICAL_STATES, make_app
from textual.widgets import Input

WIDE = (120, 40)
COMPACT = (80, 24)


def steady(pilot) -> None:
    """No blinking cursor, so two runs give the same picture."""
    for widget in pilot.app.query(Input):
        widget.cursor_blink = False


@pytest.mark.parametrize(
    "state, size",
    [
        ("default", WIDE),
        ("default", COMPACT),
        ("rich_0.20", WIDE),
        ("slow_0.20", WIDE),  # negative inertia flagged as failing I > 0
        ("slow_0.20", COMPACT),
        ("holds", WIDE),  # rank 1: readouts unavailable, charts without lines
    ],
    ids=lambda value: f"{value[0]}x{value[1]}" if isinstance(value, tuple) else value,
)
def test_tour_stop(snap_compare, state, size):
    assert snap_compare(make_app(CANONICAL_STATES[state]), terminal_size=size, run_before=steady)


def test_help_screen(snap_compare):
    assert snap_compare(make_app(), press=["question_mark"], terminal_size=WIDE,
                        run_before=steady)


def test_too_small_terminal(snap_compare):
    assert snap_compare(make_app(), terminal_size=(60, 18), run_before=steady)
