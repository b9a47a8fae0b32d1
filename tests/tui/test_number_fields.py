"""Typing into number fields: each new value replaces the last, bad text is never stepped past, letters type."""

from __future__ import annotations

from dataclasses import replace

from support.bursts import send_burst, with_app
from support.tui_support import run_app

from jointid.synthetic.settings import DEFAULT_SETTINGS
from tui.screens.matrix import MatrixScreen
from tui.screens.residuals import ResidualScreen
from tui.screens.sweep import SweepScreen
from tui.widgets.footer import KeyFooter
from tui.widgets.stepper import Stepper


def run(scenario, settings=DEFAULT_SETTINGS, size=(120, 40)):
    """Run scenario(pilot, app) against a fresh app and return its result."""
    return run_app(scenario, settings, size)


def refusals(app) -> list[str]:
    return [n.message for n in app._notifications if n.title == "Value refused"]


async def focus(pilot, app, field: str) -> Stepper:
    stepper = app.screen.query_one(f"#{field}", Stepper)
    stepper.focus()
    await pilot.pause()
    return stepper


def test_after_enter_the_next_digits_start_a_new_value():
    """3, Enter, then 1 0 gave '310' (and 241 was refused as '31241'): Enter now selects the text."""

    async def scenario(pilot, app):
        stepper = await focus(pilot, app, "samples")
        await pilot.press("3", "enter")
        await pilot.pause()
        first = app.screen.settings.samples
        await pilot.press("1", "0", "enter")
        await pilot.pause()
        second = app.screen.settings.samples
        await pilot.press("2", "4", "1", "enter")
        await pilot.pause()
        return first, second, app.screen.settings.samples, stepper.value, refusals(app)

    first, second, third, text, refused = run(scenario)
    assert (first, second, third, text) == (3, 10, 10, "10")
    assert len(refused) == 1 and "got '241'" in refused[0]


def test_after_a_refusal_and_after_a_step_typing_starts_afresh():
    async def scenario(pilot, app):
        stepper = await focus(pilot, app, "samples")
        await pilot.press("9", "9", "9", "enter")  # refused
        await pilot.press("5", "0", "enter")
        after_refusal = app.screen.settings.samples
        await pilot.press("right", "3", "0", "enter")
        await pilot.pause()
        return after_refusal, app.screen.settings.samples, stepper.value

    assert run(scenario) == (50, 30, "30")


def test_left_right_on_text_that_is_not_a_number_refuse_it_and_do_not_step():
    """8000k then Right stepped the old seed silently (x here: k toggles the constraint)."""

    async def scenario(pilot, app):
        stepper = await focus(pilot, app, "seed")
        await pilot.press(*"8000x", "right")
        await pilot.pause()
        return app.screen.settings.seed, stepper.value, refusals(app)

    seed, text, refused = run(scenario)
    assert (seed, text) == (7, "7")
    assert len(refused) == 1 and "got '8000x'" in refused[0] and "Kept 7" in refused[0]


def test_left_right_on_a_typed_number_step_from_it():
    async def scenario(pilot, app):
        await focus(pilot, app, "seed")
        await pilot.press(*"8000", "right")
        await pilot.pause()
        after_right = app.screen.settings.seed
        await pilot.press(*"50", "shift+left")
        await pilot.pause()
        return after_right, app.screen.settings.seed, refusals(app)

    assert run(scenario) == (8001, 0, [])  # 50 - 100 clamps to the seed's lowest, 0


async def open_sweep(pilot) -> SweepScreen:
    await pilot.press("s")
    await pilot.app.workers.wait_for_complete()
    await pilot.pause()
    return pilot.app.screen


def test_c_and_g_type_into_the_seed_count_while_one_types_there():
    """In the sweep field, "abc" became "ab": c cancelled (and g ran) instead of typing."""
    # Pilot waits after each key; the burst test below sends them as fast typing does.

    async def scenario(pilot, app):
        screen = await open_sweep(pilot)
        stepper = screen.query_one(Stepper)
        await pilot.press("a", "b", "c")
        typed = stepper.value
        footer = screen.query_one("KeyFooter").entries
        await pilot.press("g", "enter")
        await app.workers.wait_for_complete()
        await pilot.pause()
        return typed, footer, stepper.value, screen.seed_count, refusals(app), screen.result.seed_count

    typed, footer, text, count, refused, swept = run(scenario, replace(DEFAULT_SETTINGS, noise=0.2))
    assert typed == "abc"
    assert not {e.keys for e in footer} & {"c", "g"}  # they type now: not offered as keys
    assert (text, count, swept) == ("1000", 1000, 1000)
    assert len(refused) == 1 and "got 'abcg'" in refused[0]


def test_c_and_g_still_cancel_and_run_when_nothing_is_typed():
    async def scenario(pilot, app):
        screen = await open_sweep(pilot)
        await pilot.press("shift+left")  # K = 1
        await app.workers.wait_for_complete()
        await pilot.press("g")
        await app.workers.wait_for_complete()
        await pilot.pause()
        state = str(screen.query_one("#sweep-state").render())
        footer = {(e.keys, e.enabled) for e in screen.query_one("KeyFooter").entries}
        return state, footer, screen.query_one(Stepper).value

    state, footer, text = run(scenario)
    assert state == "done: 1 seed" and text == "1"
    assert {("c", True), ("g", True)} <= footer


def test_c_typed_quickly_after_other_letters_is_typed_too():
    """Typed fast (tmux sends "abc" in one write), c was still taken as Cancel: a priority binding
    is decided when the key arrives, before the field has taken the keys before it."""
    from textual import events

    async def scenario(pilot, app):
        screen = await open_sweep(pilot)
        for character in "abc":
            event = events.Key(character, character)
            event.set_sender(app)
            app._driver.send_message(event)  # all three queued before any is handled
        await pilot.pause()
        return screen.query_one(Stepper).value, str(screen.query_one("#sweep-state").render())

    assert run(scenario) == ("abc", "done: 1000 seeds")


@with_app
async def test_e_opens_the_residuals_from_a_number_field_that_a_view_left_focused(pilot, app, watch):
    """After m and Escape the focus was back in the noise field and e typed 'e' there ('e23'); e cannot start a
    number, so with nothing typed it is the view's key wherever the focus is (issue 24, item 6)."""
    screen = app.screen
    noise = screen.query_one("#noise", Stepper)
    noise.focus()
    send_burst(app, "m")
    await watch.until(app, lambda: isinstance(app.screen, MatrixScreen), "the matrix view")
    send_burst(app, "escape")
    await watch.until(app, lambda: app.screen is screen, "the main screen")
    assert screen.focused is noise
    send_burst(app, "e")
    await watch.until(app, lambda: isinstance(app.screen, ResidualScreen), "the residual view")
    assert noise.value == "0.00"
    send_burst(app, "escape")
    await watch.until(app, lambda: app.screen is screen, "the main screen")
    send_burst(app, "1", "e", "-", "2", "enter")  # within a number e is its exponent
    await watch.until(app, lambda: app.screen is screen and screen.settings.noise == 0.01, "1e-2 typed as the noise")
    assert noise.value == "0.01"


@with_app
async def test_the_footer_keeps_e_while_a_number_field_only_shows_its_value(pilot, app, watch):
    screen = app.screen
    footer = screen.query_one(KeyFooter)
    screen.query_one("#noise", Stepper).focus()
    await watch.until(app, lambda: "Motion" not in footer.text, "the footer of a focused number field (digits type)")
    assert "e Residuals" in footer.text
    send_burst(app, "3")
    await watch.until(app, lambda: "Residuals" not in footer.text, "e to leave the footer while a number is typed")
