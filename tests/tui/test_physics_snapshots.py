"""Snapshots of missing physics in the explorer: the ladder view, a Coulomb joint under the plain model
with its residual step, and the constrained slow fit, each at 120x40 and 80x24.

Regenerate on purpose with `pytest tests/tui/test_physics_snapshots.py --snapshot-update`,
then render each changed SVG to PNG and look at it before committing.
"""

from __future__ import annotations

from dataclasses import replace

import pytest
from support.tui_support import make_app
from test_view_snapshots import open_view

from jointid.synthetic.settings import DEFAULT_SETTINGS

SIZES = {"120x40": (120, 40), "80x24": (80, 24)}
COULOMB = replace(DEFAULT_SETTINGS, noise=0.05, samples=120, true_coulomb=0.3)
"""A Coulomb joint (FC = 0.3 N m) under the plain model; 120 samples so the step at qd = 0 reads clearly."""
CONSTRAINED_SLOW = replace(DEFAULT_SETTINGS, motion="slow", noise=0.2, constrained=True)


async def steady(pilot) -> None:
    await pilot.pause()


@pytest.mark.parametrize("size", SIZES)
def test_ladder_view(snap_compare, size):
    assert snap_compare(make_app(COULOMB), terminal_size=SIZES[size], run_before=open_view("l"))


@pytest.mark.parametrize("size", SIZES)
def test_coulomb_joint_under_the_plain_model(snap_compare, size):
    assert snap_compare(make_app(COULOMB), terminal_size=SIZES[size], run_before=steady)


@pytest.mark.parametrize("size", SIZES)
def test_coulomb_residual_step_against_velocity(snap_compare, size):
    async def run_before(pilot) -> None:
        await open_view("e")(pilot)
        await pilot.press("3")
        await pilot.pause()

    assert snap_compare(make_app(COULOMB), terminal_size=SIZES[size], run_before=run_before)


@pytest.mark.parametrize("size", SIZES)
def test_constrained_slow_fit(snap_compare, size):
    assert snap_compare(make_app(CONSTRAINED_SLOW), terminal_size=SIZES[size], run_before=steady)
