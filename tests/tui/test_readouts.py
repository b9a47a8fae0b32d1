"""Pinned readouts: the text the explorer displays for the lesson's four tour stops.

A change to any readout shows up here as a one-line diff. To regenerate the
pinned files on purpose (then review `git diff snapshots/readouts`):

    .venv/bin/python tests/support/tui_support.py
"""

from __future__ import annotations

import asyncio

import pytest
from support.tui_support import READOUTS_DIR, pinned_readouts, read_displayed

PINNED = pinned_readouts()


@pytest.mark.parametrize("name", sorted(PINNED))
def test_displayed_readouts_match_pinned_text(name):
    """The app shows exactly the pinned readout lines and status sentence (lab labels and compact rows)."""
    pinned = (READOUTS_DIR / f"{name}.txt").read_text(encoding="utf-8")
    assert asyncio.run(read_displayed(*PINNED[name])) == pinned


def test_every_pinned_file_belongs_to_a_state():
    """No orphaned readout file lingers after a state is renamed or removed."""
    pinned = {path.stem for path in READOUTS_DIR.glob("*.txt")}
    assert pinned == set(PINNED)


@pytest.mark.parametrize("width, expected", [
    (40, ["tau0 -0.014924 ± 0.005558 not determined"]),
    (38, ["tau0 -0.014924 ± 0.005558", "  not determined"]),
    (20, ["tau0 -0.014924", "  ± 0.005558 not determined"]),
])
def test_a_compact_row_too_wide_keeps_the_value_with_its_error(width, expected):
    """At 80x24 the panel is 38 columns: a long symbol with a negative value moves its verdict under the value and
    its error, not the error away from its value."""
    from jointid.present.readouts import PrecisionNote, Readout
    from tui.widgets.readouts import compact_parameter_lines

    lines = compact_parameter_lines(Readout("tau0", "Torque bias (N m)", "-0.014924"),
                                    PrecisionNote("tau0", "± 0.005558", "not determined"), width)
    assert [line.plain for line in lines] == expected
