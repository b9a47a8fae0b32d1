"""The explorer's design view: run, cancel, train on the design (a fourth motion), save it, refuse bad limits."""

from __future__ import annotations

import os
import signal
from dataclasses import replace
from functools import partial

import numpy as np
from support.design_stand_ins import broken_design, gone
from support.tui_support import run_app, time_limit
from textual.widgets import ProgressBar, Static

from jointid.studies import design_process
from jointid.synthetic.fourier import FourierMotion, load_motion
from jointid.synthetic.settings import Settings
from tui.screens.design import DesignScreen
from tui.screens.main import MainScreen
from tui.widgets.direct_controls import ChoiceList

NOISY = Settings(noise=0.2)


async def open_design(pilot):
    await pilot.press("d")
    await pilot.pause()
    assert isinstance(pilot.app.screen, DesignScreen)
    return pilot.app.screen


async def run_design(pilot):
    screen = await open_design(pilot)
    await pilot.press("g")
    await pilot.app.workers.wait_for_complete()
    await pilot.pause()
    return screen


def text_of(screen, selector: str) -> str:
    return str(screen.query_one(selector, Static).render())


def test_a_run_shows_the_design_beside_rich_motion():
    async def scenario(pilot, app):
        screen = await run_design(pilot)
        return screen.result, text_of(screen, "#design-table"), text_of(screen, "#design-verdict"), \
            text_of(screen, "#design-state")

    result, table, verdict, state = run_app(scenario, NOISY)
    assert result is not None and result.spec.criterion == "d"
    assert "designed SE" in table and "rich SE" in table and "0.01695" in table  # rich's I at noise 0.20
    assert verdict.startswith("Every parameter is determined at least as well")
    assert state == "done: 8 of 8 starts"


def test_the_cond_criterion_is_shown_as_the_counter_example():
    async def scenario(pilot, app):
        screen = await open_design(pilot)
        screen.query_one("#criterion", ChoiceList).focus()
        await pilot.press("down", "down", "enter", "g")
        await app.workers.wait_for_complete()
        await pilot.pause()
        return screen.result, text_of(screen, "#design-verdict")

    result, verdict = run_app(scenario, NOISY)
    assert result.spec.criterion == "cond" and result.design.condition_number < 1.1
    assert verdict.startswith("Worse than rich motion: I (SE") and "condition number near 1" in verdict


def test_noise_0_still_gives_standard_errors_at_the_lessons_noise():
    async def scenario(pilot, app):
        screen = await open_design(pilot)
        return screen.experiment.noise, text_of(screen, "#design-title")

    noise, title = run_app(scenario, Settings())
    assert noise == 0.2 and "noise 0.20 N m" in title


def long_designs(monkeypatch):
    """Make the view's designs take 1000 starts (minutes), so a test can act while one runs."""
    original = DesignScreen.spec
    monkeypatch.setattr(DesignScreen, "spec", lambda self: replace(original(self), starts=1000))


def test_cancel_stops_a_running_design_and_escape_then_returns(monkeypatch):
    long_designs(monkeypatch)

    async def scenario(pilot, app):
        screen = await open_design(pilot)
        await pilot.press("g", "c")
        await app.workers.wait_for_complete()
        await pilot.pause()
        state, result = text_of(screen, "#design-state"), screen.result
        await pilot.press("escape")
        await pilot.pause()
        return state, result, app.screen

    state, result, back = run_app(scenario, NOISY)
    assert state == "cancelled" and result is None and isinstance(back, MainScreen)


def test_train_adds_a_fourth_motion_and_4_returns_to_it():
    async def scenario(pilot, app):
        screen = await run_design(pilot)
        designed = screen.result.motion
        await pilot.press("t")
        await pilot.pause()
        main = app.screen
        trained = main.settings.motion
        await pilot.press("1")
        await pilot.pause()
        rich = main.settings.motion
        await pilot.press("4")
        await pilot.pause()
        motions = main.query_one("#motion", ChoiceList)
        return designed, trained, rich, main.settings.motion, motions.pressed, motions.hidden, main.result

    designed, trained, rich, again, pressed, hidden, result = run_app(scenario, NOISY)
    assert isinstance(trained, FourierMotion) and trained == designed and rich == "rich" and again == designed
    assert pressed == "motion-design" and "motion-design" not in hidden
    assert result.rank == 3  # the fit on screen is the designed motion's
    np.testing.assert_array_equal(result.training.qdd, designed.states(np.linspace(0.0, 8.0, 24)).qdd)


def test_4_does_nothing_before_a_design_exists():
    async def scenario(pilot, app):
        await pilot.press("4")
        await pilot.pause()
        return app.screen.settings.motion, app.screen.query_one("#motion", ChoiceList).hidden

    motion, hidden = run_app(scenario, NOISY)
    assert motion == "rich" and "motion-design" in hidden


def test_save_writes_a_motion_file_that_loads_back_bit_for_bit(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)

    async def scenario(pilot, app):
        screen = await run_design(pilot)
        await pilot.press("w", "w")  # the second save takes the next free name
        await pilot.pause()
        return screen.result.motion

    motion = run_app(scenario, NOISY)
    first, second = load_motion(tmp_path / "jointid-design-d.json"), load_motion(tmp_path / "jointid-design-d-2.json")
    assert first == motion and second == motion
    assert np.array_equal(first.coefficients, motion.coefficients)


def test_a_bad_limit_is_refused_with_a_notification_and_the_value_kept():
    async def scenario(pilot, app):
        screen = await open_design(pilot)
        await pilot.press("0", "enter")  # |q| max = 0 (typing replaces the selected value)
        await pilot.pause()
        return screen.limits["q_max"], [n.message for n in app._notifications]

    value, messages = run_app(scenario, NOISY)
    assert value == 0.95 and any("|q| max must be a number" in m for m in messages)


def test_an_inconsistent_torque_limit_is_a_notification_not_a_run():
    async def scenario(pilot, app):
        screen = await open_design(pilot)
        screen.limits["tau_max"] = 1.0  # below the 3.5 N m that holding the joint at |q| <= 0.95 takes
        await pilot.press("g")
        await app.workers.wait_for_complete()
        await pilot.pause()
        return screen.result, [n.message for n in app._notifications]

    result, messages = run_app(scenario, NOISY)
    assert result is None and any("inconsistent" in m for m in messages)


def test_the_design_view_fits_80x24():
    async def scenario(pilot, app):
        screen = await run_design(pilot)
        regions = {name: screen.query_one(f"#{name}").region for name in
                   ("design-title", "q_max", "tau_max", "criterion", "design-state", "design-chart", "design-body")}
        return regions, app.size

    regions, size = run_app(scenario, NOISY, size=(80, 24))
    for name, region in regions.items():
        assert region.width > 0 and region.height > 0, name
        assert region.right <= size.width and region.bottom <= size.height - 1, name  # above the footer


def test_escape_cancels_a_running_design_first(monkeypatch):
    long_designs(monkeypatch)

    async def scenario(pilot, app):
        screen = await open_design(pilot)
        await pilot.press("g")
        await pilot.pause(0.2)
        running = screen.running
        await pilot.press("escape")
        await app.workers.wait_for_complete()
        await pilot.pause()
        return running, app.screen is screen, text_of(screen, "#design-state")

    running, stayed, state = run_app(scenario, NOISY)
    assert running and stayed and state == "cancelled"


def test_the_explorer_opens_on_a_motion_file_as_its_fourth_motion():
    motion = FourierMotion(8.0, 0.0, (0.0, 0.0, 1.2), (0.0, 0.0, 0.4))

    async def scenario(pilot, app):
        motions = app.screen.query_one("#motion", ChoiceList)
        return motions.pressed, motions.hidden, app.screen.designed

    pressed, hidden, designed = run_app(scenario, Settings(motion=motion, noise=0.2))
    assert pressed == "motion-design" and "motion-design" not in hidden and designed == motion


async def running_design_pid(pilot, screen) -> int:
    """Press g and wait until the view's design process is optimising (its first start reported)."""
    await pilot.press("g")
    for _ in range(600):  # the child's start-up (imports) takes about a second here
        if screen.designer is not None and screen.designer.pid is not None and screen.query_one(ProgressBar).progress:
            return screen.designer.pid
        await pilot.pause(0.05)
    raise AssertionError("the design process never reported a start")


def test_cancel_kills_the_design_process(monkeypatch):
    long_designs(monkeypatch)

    async def scenario(pilot, app):
        screen = await open_design(pilot)
        pid = await running_design_pid(pilot, screen)
        await pilot.press("c")
        await app.workers.wait_for_complete()
        await pilot.pause()
        return pid, screen.designer.pid, text_of(screen, "#design-state")

    with time_limit(120):
        pid, now, state = run_app(scenario, NOISY)
    assert gone(pid) and now is None and state == "cancelled"


def test_quitting_while_a_design_runs_leaves_no_process(monkeypatch):
    long_designs(monkeypatch)

    async def scenario(pilot, app):
        screen = await open_design(pilot)
        pid = await running_design_pid(pilot, screen)
        await pilot.press("ctrl+q")
        return pid

    with time_limit(120):
        pid = run_app(scenario, NOISY)
    assert gone(pid)


def test_closing_the_view_ends_its_idle_design_process():
    async def scenario(pilot, app):
        screen = await run_design(pilot)
        pid = screen.designer.pid  # the child waits for the next design
        alive = not gone(pid)
        await pilot.press("escape")
        await pilot.pause()
        return pid, alive, app.screen

    pid, alive, back = run_app(scenario, NOISY)
    assert alive and gone(pid) and isinstance(back, MainScreen)


def test_a_failure_inside_the_optimiser_is_a_notification(monkeypatch):
    monkeypatch.setattr(design_process, "DesignProcess", partial(design_process.DesignProcess, broken_design))

    async def scenario(pilot, app):
        screen = await run_design(pilot)
        return screen.result, text_of(screen, "#design-state"), [(n.title, n.message) for n in app._notifications]

    result, state, notes = run_app(scenario, NOISY)
    assert result is None and state == "no design"
    assert ("No design", "the optimiser failed: ZeroDivisionError: division by zero") in notes


def test_a_design_process_killed_from_outside_is_a_notification(monkeypatch):
    long_designs(monkeypatch)

    async def scenario(pilot, app):
        screen = await open_design(pilot)
        pid = await running_design_pid(pilot, screen)
        os.kill(pid, signal.SIGKILL)
        await app.workers.wait_for_complete()
        await pilot.pause()
        return text_of(screen, "#design-state"), [n.message for n in app._notifications]

    with time_limit(120):
        state, messages = run_app(scenario, NOISY)
    assert state == "no design" and "the optimiser's process stopped (exit status -9)" in messages


def test_a_design_over_the_work_budget_is_refused_with_a_notification_and_no_process(monkeypatch):
    """`jointid design` refuses a design over its work budget; the view ran any design it was given."""
    from jointid.studies import design

    monkeypatch.setattr(design, "DESIGN_BUDGET_SECONDS", 1e-6)  # the explorer's own designs fit the real one

    async def scenario(pilot, app):
        screen = await open_design(pilot)
        await pilot.press("g")
        await pilot.app.workers.wait_for_complete()
        await pilot.pause()
        return screen.designer, screen.result, text_of(screen, "#design-state"), \
            [n.message for n in app._notifications]

    designer, result, state, messages = run_app(scenario, NOISY)
    assert designer is None and result is None and not state.startswith("running")
    assert len(messages) == 1 and "over the 1e-06 s budget" in messages[0] and "lower the samples" in messages[0]
    assert messages[0].startswith("A design of 8 starts x 3 harmonics x 24 samples for the 3-parameter plain model")
