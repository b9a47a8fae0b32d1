"""Pilot tests of missing physics in the explorer: the physics dialog, the constraint key, the ladder
view, the palette's stops beyond the lesson, and a log refitted with another model."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from textual.geometry import Region
from support.tui_support import run_app as run

from jointid.present.comparison import comparison_table
from jointid.present.readouts import readouts
from jointid.studies.experiment import run_experiment
from jointid.studies.ladder import compare_experiment
from jointid.synthetic.fourier import FourierMotion
from jointid.synthetic.settings import DEFAULT_SETTINGS
from tui.palette import PHYSICS_STOPS
from tui.screens.ladder import LadderScreen
from tui.screens.physics import PhysicsScreen
from tui.widgets.direct_controls import ChoiceList
from tui.widgets.readouts import ReadoutPanel
from tui.widgets.stepper import Stepper


def shown_readouts(screen) -> tuple:
    return screen.query_one(ReadoutPanel).items


def test_the_physics_dialog_changes_the_true_joint_and_the_model_at_once():
    async def scenario(pilot, app):
        main = app.screen
        await pilot.press("p")
        await pilot.pause()
        dialog = app.screen
        assert isinstance(dialog, PhysicsScreen)
        # Coulomb friction: the focused first field, stepped six times by 0.05 N m.
        for _ in range(6):
            await pilot.press("right")
        await pilot.pause()
        after_friction = main.settings
        dialog.query_one("#model", ChoiceList).focus()
        await pilot.press("down", "enter")
        await pilot.pause()
        after_model = main.settings
        await pilot.press("escape")
        await pilot.pause()
        return after_friction, after_model, shown_readouts(main), app.screen is main

    after_friction, after_model, items, back = run(scenario)
    assert after_friction == replace(DEFAULT_SETTINGS, true_coulomb=0.3)
    assert after_model == replace(DEFAULT_SETTINGS, true_coulomb=0.3, model="coulomb")
    assert items == readouts(run_experiment(after_model)) and back
    np.testing.assert_allclose([float(i.text) for i in items[1:5]], [0.8, 0.4, 0.15, 0.3], atol=1e-6)


def test_escape_closes_the_dialog_from_its_focused_first_field_and_first_discards_typing():
    async def scenario(pilot, app):
        main = app.screen
        seen = []
        for typed in ((), ("1",)):
            await pilot.press("p")
            await pilot.pause()
            field = app.screen.focused
            await pilot.press(*typed, "escape")
            await pilot.pause()
            seen.append((isinstance(field, Stepper) and field.id == "true_coulomb", field.value,
                         isinstance(app.screen, PhysicsScreen)))
            if app.screen is not main:
                await pilot.press("escape")
                await pilot.pause()
            seen.append(app.screen is main)
        return main.settings, seen

    settings, seen = run(scenario)
    # Nothing typed: one Escape closes. Typed: the first Escape discards it in the still open dialog.
    assert seen == [(True, "0.00", False), True, (True, "0.00", True), True]
    assert settings == DEFAULT_SETTINGS


def test_a_refused_physics_value_keeps_the_setting():
    async def scenario(pilot, app):
        main = app.screen
        await pilot.press("p")
        await pilot.pause()
        field = app.screen.query_one("#true_angle_offset", Stepper)
        field.focus()
        await pilot.pause()
        field.value = "0.9"
        await pilot.press("enter")
        await pilot.pause()
        return main.settings, field.value, [n.severity for n in app._notifications]

    settings, text, severities = run(scenario)
    assert settings.true_angle_offset == 0.0 and text == "0.00" and severities == ["error"]


def test_k_toggles_the_sign_constraint_and_the_title_says_so():
    async def scenario(pilot, app):
        await pilot.press("2")  # slow motion
        main = app.screen
        main.query_one("#noise", Stepper).focus()
        await pilot.press("shift+right", "shift+right")
        await pilot.press("k")
        await pilot.pause()
        constrained = (main.settings, shown_readouts(main), str(main.query_one("#title").render()))
        await pilot.press("k")
        await pilot.pause()
        return constrained, main.settings

    (settings, items, title), after = run(scenario)
    assert settings == replace(DEFAULT_SETTINGS, motion="slow", noise=0.2, constrained=True)
    assert items == readouts(run_experiment(settings)) and "constrained" in title
    assert dict((i.key, i.text) for i in items)["I"] == "0.000001"
    assert after.constrained is False


def test_the_ladder_view_shows_the_core_s_comparison_and_simulates_every_model():
    settings = replace(DEFAULT_SETTINGS, noise=0.05, true_coulomb=0.3)

    async def scenario(pilot, app):
        await pilot.press("l")
        await pilot.pause()
        view = app.screen
        await app.workers.wait_for_complete()
        await pilot.pause()
        return (isinstance(view, LadderScreen), str(view.query_one("#ladder-table").render()),
                str(view.query_one("#ladder-simulation").render()), dict(view.simulations))

    is_ladder, table, simulation, checks = run(scenario, settings)
    assert is_ladder and table == comparison_table(compare_experiment(settings))
    assert set(checks) == {"plain", "coulomb", "bias", "angle-offset", "coulomb+bias", "coulomb+angle-offset"}
    assert checks["plain"].rmse >= 10 * checks["coulomb"].rmse
    assert "…" not in simulation


@pytest.mark.parametrize("index", range(len(PHYSICS_STOPS)))
def test_the_palette_stops_beyond_the_lesson_set_their_settings(index):
    title, settings, _ = PHYSICS_STOPS[index]

    async def scenario(pilot, app):
        await pilot.press("ctrl+p")
        await pilot.pause()
        await pilot.press(*title)
        await pilot.pause()
        await pilot.press("enter")
        await pilot.pause()
        return app.screen.settings, shown_readouts(app.screen)

    shown, items = run(scenario)
    assert shown == settings and items == readouts(run_experiment(settings))


def damping_row(main) -> tuple[Region, str]:
    """The screen region of the readout panel's damping row, and that row's text."""
    panel = main.query_one(ReadoutPanel)
    lines = [line.plain for line in panel.lines(panel.content_region.width)]
    index = next(i for i, line in enumerate(lines) if line.startswith(("B ", "Fitted damping")))
    content = panel.content_region
    return Region(content.x, content.y + index, content.width, 1), lines[index]


@pytest.mark.parametrize("size", [(80, 24), (120, 40)], ids=["80x24", "120x40"])
def test_the_physics_dialog_leaves_the_damping_readout_in_view_while_fc_changes_it(size):
    async def scenario(pilot, app):
        main = app.screen
        await pilot.press("p")
        await pilot.pause()  # the dialog's first layout
        dialog = app.screen
        box = dialog.query_one("#physics").region
        before_region, before = damping_row(main)
        for _ in range(6):  # FC from 0 to 0.3 N m: the plain model takes it for damping
            await pilot.press("right")
        after_region, after = damping_row(main)
        return dialog, app.screen, box, before_region, before, after_region, after

    dialog, still_open, box, before_region, before, after_region, after = run(scenario, size=size)
    assert isinstance(dialog, PhysicsScreen) and still_open is dialog
    assert box and before_region and before_region.width >= len(before.rstrip())
    assert not box.overlaps(before_region) and not box.overlaps(after_region)
    assert box.bottom <= size[1] - 1  # the whole dialog is on screen, above its footer
    assert "0.150000" in before and "0.449309" in after  # B grows from the true 0.15 while the dialog is open


DESIGNED_MOTION = FourierMotion(8.0, 0.0, (0.0, 0.0, 1.2), (0.0, 0.0, 0.4))
"""A designed motion as the explorer holds it after the design view's t (or --motion-file): the list's fourth."""


@pytest.mark.parametrize("size, settings, choose_model", [
    ((80, 24), replace(DEFAULT_SETTINGS, motion=DESIGNED_MOTION, noise=0.2), True),
    ((120, 40), replace(DEFAULT_SETTINGS, motion=DESIGNED_MOTION, noise=0.2), True),
    ((80, 24), replace(DEFAULT_SETTINGS, noise=1.0), False),
    ((80, 24), replace(DEFAULT_SETTINGS, motion="slow", noise=1.0), False),
    ((120, 40), replace(DEFAULT_SETTINGS, noise=0.2, constrained=True, true_coulomb=0.3, model="coulomb+bias"), False),
    ((80, 24), replace(DEFAULT_SETTINGS, motion="holds", noise=0.2, model="coulomb+angle-offset"), False),
], ids=["80x24-designed-five-terms", "120x40-designed-five-terms", "80x24-plain-noise-1", "80x24-slow-noise-1",
        "120x40-constrained-five-terms", "80x24-holds-rank-1-of-5"])
def test_every_readout_fits_the_side_panel_without_scrolling(size, settings, choose_model):
    """A designed motion with the coulomb+bias model gave the side panel a scrollbar at 80x24 and 120x40 (the
    status took six rows, the fifth parameter's row wrapped beside the bar); so did plain noise 1.0 at 80x24
    (slow motion's two sign failures too), a constrained five-term fit at 120x40 and a rank-deficient one at 80x24."""

    async def scenario(pilot, app):
        main = app.screen
        if choose_model:
            await pilot.press("p")
            await pilot.pause()
            app.screen.query_one("#model", ChoiceList).focus()
            await pilot.press("down", "down", "down", "down", "enter", "escape")
            await pilot.pause()
        side, panel = main.query_one("#side"), main.query_one(ReadoutPanel)
        lines = [line.plain for line in panel.lines(panel.content_region.width)]
        return main.settings.model, side.max_scroll_y, panel.region, side.content_region, lines

    model, scroll, panel, side, lines = run(scenario, settings, size=size)
    assert model == ("coulomb+bias" if choose_model else settings.model)
    assert scroll == 0 and panel.bottom <= side.bottom and panel.right <= side.right
    text = "\n".join(lines)
    assert "Cond" in text and "Held-out RMSE" in text  # the last readouts are in the panel, which is all on screen
    assert ("tau0" in text or "torque bias" in text) == (choose_model or settings.model == "coulomb+bias")


def test_slow_motions_sign_failures_share_a_row_when_a_designed_motion_takes_one():
    """The last case that scrolled at 80x24: a designed motion in the list (a fourth row), then slow motion at noise
    0.2 under coulomb+bias, whose h and Fc both fail their signs and whose tau0 row wraps. The two failures then
    share one row, and every readout stays on screen."""

    async def scenario(pilot, app):
        main = app.screen
        await pilot.press("2")
        await pilot.pause()
        side, panel = main.query_one("#side"), main.query_one(ReadoutPanel)
        lines = [line.plain for line in panel.lines(panel.content_region.width)]
        return main.settings.motion_name, side.max_scroll_y, lines

    settings = replace(DEFAULT_SETTINGS, motion=DESIGNED_MOTION, noise=0.2, model="coulomb+bias")
    motion, scroll, lines = run(scenario, settings, size=(80, 24))
    assert motion == "slow" and scroll == 0
    failures = [line for line in lines if "✗" in line]
    assert [line.strip() for line in failures] == ["✗ h ≥ 0, Fc ≥ 0 fail"]
    assert any("Cond" in line for line in lines) and any("Held-out RMSE" in line for line in lines)
