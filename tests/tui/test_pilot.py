"""Pilot tests: every key and control of the explorer changes state, and the readouts follow."""

from __future__ import annotations

from dataclasses import replace

import pytest
from support.tui_support import run_app
from textual.widgets import Input

from jointid.options import SEED_LIMITS
from jointid.present.readouts import readouts
from jointid.present.status import status_message
from jointid.studies.experiment import run_experiment
from jointid.synthetic.motions import TRAINING_MOTIONS
from jointid.synthetic.settings import DEFAULT_SETTINGS, Settings
from tui.palette import TOUR, tour_title
from tui.ranges import NOISE_RANGE, SAMPLES_RANGE, SEED_RANGE
from tui.screens.main import MOTION_KEYS, MainScreen
from tui.sizes import MIN_SIZE
from tui.widgets.charts import TorqueChart
from tui.widgets.direct_controls import ChoiceList
from tui.widgets.readouts import ReadoutPanel
from tui.widgets.stepper import Stepper

SIZE = (120, 40)


def run(scenario, settings: Settings | None = None, size=SIZE):
    """Run an async scenario(pilot, screen) against a fresh app and return its result."""
    return run_app(lambda pilot, app: scenario(pilot, app.screen), settings, size)


def assert_shows(screen: MainScreen, settings: Settings) -> None:
    """The screen holds these settings, its controls show them, and its readouts are the core's."""
    assert screen.settings == settings
    expected = readouts(run_experiment(settings))
    assert screen.query_one(ReadoutPanel).items == expected
    shown = "\n".join(line.plain for line in screen.query_one(ReadoutPanel).lines(200))
    for item in expected:
        assert f"{item.label}" in shown and item.text in shown
    assert str(screen.query_one("#status").render()) == status_message(run_experiment(settings))
    assert screen.query_one(ChoiceList).pressed == f"motion-{settings.motion}"
    for stepper in screen.query(Stepper):
        assert stepper.number == getattr(settings, stepper.field)
        assert stepper.value == stepper.steps.format(getattr(settings, stepper.field))


async def focus(pilot, screen, field: str) -> Stepper:
    stepper = screen.query_one(f"#{field}", Stepper)
    stepper.focus()
    await pilot.pause()
    return stepper


async def type_value(pilot, screen, field: str, text: str) -> None:
    """Focus a number field (which selects its text), type over it and press Enter."""
    await focus(pilot, screen, field)
    await pilot.press(*(list(text) or ["backspace"]), "enter")  # backspace clears the selection
    await pilot.pause()


def test_opens_at_the_lesson_defaults():
    async def scenario(pilot, screen):
        assert_shows(screen, DEFAULT_SETTINGS)

    run(scenario)


def test_opens_at_given_settings():
    settings = Settings(motion="slow", noise=0.2, samples=30, seed=11)

    async def scenario(pilot, screen):
        assert_shows(screen, settings)

    run(scenario, settings)


@pytest.mark.parametrize("key", sorted(MOTION_KEYS))
def test_motion_keys_select_each_motion(key):
    motion = MOTION_KEYS[key][0]
    start = replace(DEFAULT_SETTINGS, motion="slow" if motion == "rich" else "rich", noise=0.2)

    async def scenario(pilot, screen):
        await pilot.press(key)
        await pilot.pause()
        assert_shows(screen, replace(start, motion=motion))

    run(scenario, start)


def test_motion_list_selects_motion_with_arrows_and_enter():
    async def scenario(pilot, screen):
        screen.query_one(ChoiceList).focus()
        await pilot.press("down", "enter")
        await pilot.pause()
        assert_shows(screen, replace(DEFAULT_SETTINGS, motion="slow"))

    run(scenario)


def pressed_motion_buttons(screen) -> list[str]:
    """The options drawn with the pressed mark (the list's own record is checked by assert_shows)."""
    choices = screen.query_one(ChoiceList)
    lines = choices.render().plain.splitlines()
    return [option for option, line in zip(choices.shown, lines) if line.startswith("▐" + ChoiceList.ON_MARK)]


@pytest.mark.parametrize("how", ["enter", "space", "click"])
def test_motion_list_presses_exactly_the_chosen_button(how):
    async def scenario(pilot, screen):
        screen.query_one(ChoiceList).focus()
        for motion in ("holds", "slow", "rich"):
            if how == "click":
                await pilot.click("#motion", offset=(4, list(TRAINING_MOTIONS).index(motion)))
            else:
                while screen.query_one(ChoiceList).highlighted != f"motion-{motion}":
                    await pilot.press("down")
                await pilot.press(how)
            await pilot.pause()
            assert pressed_motion_buttons(screen) == [f"motion-{motion}"]
            assert_shows(screen, replace(DEFAULT_SETTINGS, motion=motion))

    run(scenario)


def test_clicking_the_pressed_motion_keeps_it_pressed():
    async def scenario(pilot, screen):
        await pilot.click("#motion", offset=(4, 0))
        await pilot.pause()
        assert pressed_motion_buttons(screen) == ["motion-rich"]
        assert_shows(screen, DEFAULT_SETTINGS)

    run(scenario)


@pytest.mark.parametrize("steps", [NOISE_RANGE, SAMPLES_RANGE, SEED_RANGE], ids=lambda s: s.field)
def test_steppers_step_small_and_big(steps):
    start = replace(DEFAULT_SETTINGS, noise=0.5)

    async def scenario(pilot, screen):
        await focus(pilot, screen, steps.field)
        value = getattr(start, steps.field)
        for key, change in (("right", steps.step), ("shift+right", steps.big_step),
                            ("left", -steps.step), ("shift+left", -steps.big_step)):
            await pilot.press(key)
            await pilot.pause()
            value = steps.clamp(value + change)
            assert_shows(screen, replace(start, **{steps.field: value}))
        assert value == getattr(start, steps.field)

    run(scenario, start)


@pytest.mark.parametrize("steps", [NOISE_RANGE, SAMPLES_RANGE, SEED_RANGE], ids=lambda s: s.field)
@pytest.mark.parametrize("end", ["low", "high"])
def test_steppers_clamp_at_both_ends(steps, end):
    limit = getattr(steps, end)
    start = replace(DEFAULT_SETTINGS, **{steps.field: limit})
    key = "shift+left" if end == "low" else "shift+right"

    async def scenario(pilot, screen):
        await focus(pilot, screen, steps.field)
        await pilot.press(key, key[6:])
        await pilot.pause()
        assert_shows(screen, start)

    run(scenario, start)


def test_noise_steps_do_not_drift():
    """A hundred 0.01 steps from 0 land exactly on 1.00, the top of the range."""

    async def scenario(pilot, screen):
        await focus(pilot, screen, "noise")
        await pilot.press(*["right"] * 100)
        await pilot.pause()
        assert screen.settings.noise == NOISE_RANGE.high
        assert screen.query_one("#noise", Stepper).value == "1.00"

    run(scenario)


@pytest.mark.parametrize(
    "field, text, value",
    [("noise", "0.35", 0.35), ("samples", "100", 100), ("seed", str(SEED_LIMITS[1]), SEED_LIMITS[1])],
)
def test_typed_values_are_committed(field, text, value):
    async def scenario(pilot, screen):
        await type_value(pilot, screen, field, text)
        assert_shows(screen, replace(DEFAULT_SETTINGS, **{field: value}))

    run(scenario)


@pytest.mark.parametrize(
    "field, text, phrase",
    [
        ("noise", "abc", "noise must be a number from 0.00 to 1.00 N m"),
        ("noise", "1.5", "noise must be a number from 0.00 to 1.00 N m"),
        ("noise", "-0.1", "noise must be a number from 0.00 to 1.00 N m"),
        ("noise", "nan", "noise must be a number from 0.00 to 1.00 N m"),
        ("samples", "241", "samples must be a whole number from 2 to 240"),
        ("samples", "1", "samples must be a whole number from 2 to 240"),
        ("samples", "2.5", "samples must be a whole number from 2 to 240"),
        ("seed", str(SEED_LIMITS[1] + 1), f"seed must be a whole number from 0 to {SEED_LIMITS[1]}"),
        ("seed", "", "seed must be a whole number"),
    ],
)
def test_invalid_typed_values_are_refused_visibly(field, text, phrase):
    start = replace(DEFAULT_SETTINGS, noise=0.2)

    async def scenario(pilot, screen):
        await type_value(pilot, screen, field, text)
        assert_shows(screen, start)
        messages = [n.message for n in pilot.app._notifications]
        assert any(phrase in m and repr(text) in m for m in messages), messages

    run(scenario, start)


def test_typed_value_is_committed_when_focus_leaves():
    async def scenario(pilot, screen):
        await focus(pilot, screen, "samples")
        await pilot.press("4", "0", "tab")
        await pilot.pause()
        assert_shows(screen, replace(DEFAULT_SETTINGS, samples=40))

    run(scenario)


def test_escape_discards_typing():
    async def scenario(pilot, screen):
        stepper = await focus(pilot, screen, "seed")
        await pilot.press("9", "9", "escape")
        await pilot.pause()
        assert stepper.value == "7"
        assert_shows(screen, DEFAULT_SETTINGS)

    run(scenario)


@pytest.mark.parametrize("how", ["key", "button", "click"])
def test_reset_restores_all_four_controls(how):
    start = Settings(motion="holds", noise=0.73, samples=99, seed=1234)

    async def scenario(pilot, screen):
        assert_shows(screen, start)
        if how == "key":
            await focus(pilot, screen, "seed")  # r works even from a number field
            await pilot.press("r")
        elif how == "button":
            screen.query_one("#reset").focus()
            await pilot.press("enter")
        else:
            await pilot.click("#reset")
        await pilot.pause()
        assert_shows(screen, DEFAULT_SETTINGS)

    run(scenario, start)


@pytest.mark.parametrize("index", range(len(TOUR)))
def test_tour_entries_in_the_palette_set_all_four_controls(index):
    start = Settings(motion="holds", noise=0.9, samples=200, seed=99)

    async def scenario(pilot, screen):
        await pilot.press("ctrl+p")
        await pilot.pause()
        await pilot.press(*tour_title(index, TOUR[index]))
        await pilot.pause(0.3)  # the palette searches in a worker
        await pilot.press("enter")
        await pilot.pause()
        assert pilot.app.screen is screen
        assert_shows(screen, TOUR[index])

    run(scenario, start)


def test_palette_offers_every_key_binding_that_works_now():
    async def scenario(pilot, screen):
        names = {command.title for command in pilot.app.get_system_commands(screen)}
        for binding in MainScreen.BINDINGS:
            if binding.tooltip and binding.action not in ("close_log", "notes", "gains", "runs", "reset_log",
                                                          "motion('design')"):
                assert binding.description in names
        assert "Close log" not in names and "Notes" not in names and "Gains" not in names  # no log is loaded
        assert "Designed" not in names  # no motion designed yet

    run(scenario)


def test_help_opens_and_escape_closes_it():
    async def scenario(pilot, screen):
        await pilot.press("question_mark")
        await pilot.pause()
        help_screen = pilot.app.screen
        assert type(help_screen).__name__ == "HelpScreen"
        text = help_screen.query_one("Markdown").source
        assert "Three things to try" in text and "- `r`: " in text
        await pilot.press("escape")
        await pilot.pause()
        assert pilot.app.screen is screen

    run(scenario)


def test_quit_key_exits():
    async def scenario(pilot, screen):
        await pilot.press("q")
        await pilot.pause()
        return pilot.app.is_running

    assert run(scenario) is False


@pytest.mark.parametrize("size", [(20, 5), (MIN_SIZE[0] - 1, MIN_SIZE[1]), (MIN_SIZE[0], MIN_SIZE[1] - 1)])
def test_too_small_terminal_asks_for_more_room_and_recovers(size):
    async def scenario(pilot, screen):
        await pilot.resize_terminal(*size)
        await pilot.pause()
        assert screen.has_class("-too-small")
        assert "enlarge" in str(screen.query_one("#too-small").render())
        await pilot.resize_terminal(*MIN_SIZE)
        await pilot.pause()
        assert not screen.has_class("-too-small")

    run(scenario)


def test_resizing_through_many_sizes_never_fails():
    async def scenario(pilot, screen):
        for width, height in [(1, 1), (10, 3), (50, 15), (80, 24), (79, 23), (200, 60), (120, 40)]:
            await pilot.resize_terminal(width, height)
            await pilot.pause()
        assert_shows(screen, DEFAULT_SETTINGS)

    run(scenario)


def test_charts_redraw_only_when_their_data_change():
    """Without noise the seed changes nothing visible, so neither chart is rebuilt."""

    async def scenario(pilot, screen):
        charts = list(screen.query(TorqueChart))
        before = [chart.draws for chart in charts]
        await focus(pilot, screen, "seed")
        await pilot.press("right")
        await pilot.pause()
        assert [chart.draws for chart in charts] == before
        await focus(pilot, screen, "noise")
        await pilot.press("right")
        await pilot.pause()
        assert [chart.draws for chart in charts] == [n + 1 for n in before]

    run(scenario)


def test_rank_deficient_charts_say_predictions_are_unavailable():
    async def scenario(pilot, screen):
        for chart in screen.query(TorqueChart):
            assert chart.data.line is None
            assert "predictions unavailable" in chart.data.summaries[0]

    run(scenario, replace(DEFAULT_SETTINGS, motion="holds"))


def test_no_input_ends_up_with_a_stale_value_after_push_down():
    """Settings pushed from above (tour, reset) replace half-typed text in every field."""

    async def scenario(pilot, screen):
        await focus(pilot, screen, "noise")
        await pilot.press("0", ".", "9")
        screen.apply_settings(TOUR[2])
        await pilot.pause()
        assert all(isinstance(s, Input) for s in screen.query(Stepper))
        assert_shows(screen, TOUR[2])

    run(scenario)


@pytest.mark.parametrize(
    "argv, phrase",
    [(["--noise", "2"], "--noise is from 0.00 to 1.00 N m"), (["--samples", "500"], "--samples is from 2 to 240")],
)
def test_command_line_refuses_values_outside_the_explorer_ranges(argv, phrase, capsys):
    """Values `jointid fit` accepts but the controls cannot show: one line, exit 2, no app."""
    from jointid.cli import main

    assert main(argv) == 2
    err = capsys.readouterr().err
    assert phrase in err and "jointid fit" in err and err.count("\n") == 1


def test_command_line_opens_the_explorer_at_the_given_settings(monkeypatch):
    """`jointid --motion slow --noise 0.2` builds the app with exactly those settings."""
    import tui.app
    from jointid.cli import main

    opened = []
    monkeypatch.setattr(tui.app.JointIdApp, "run", lambda self: opened.append(self.initial_settings))
    assert main(["--motion", "slow", "--noise", "0.2", "--samples", "30", "--seed", "3"]) == 0
    assert opened == [Settings(motion="slow", noise=0.2, samples=30, seed=3)]
