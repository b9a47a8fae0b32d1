"""Key storms: thousands of seeded random keys and resizes through every view; the app never freezes or
crashes, and at the end its readouts are the core's for the settings it shows.

Keys arrive in bursts of one to six without waiting in between, as from fast typing or
key repeat, so a burst can cross from one screen into the next. Dialogs are always left
with Escape (the storm runs in a temporary folder all the same). `q` is not in the
alphabet: quitting is tested elsewhere. The fast storm runs in the default suite; the
10,000-key one is marked `slow` (`pytest -m slow tests/tui/test_storm.py`). Each storm first opens every view
and dialog once, and one starts on several runs of a log so that the log's views are stormed too.
"""

from __future__ import annotations

import asyncio
import random
import unicodedata
from dataclasses import dataclass

import pytest
from support.tui_support import make_app, time_limit
from textual import events
from textual.content import Content
from textual.keys import REPLACED_KEYS, _character_to_key, _get_unicode_name_from_key

from jointid.present.charts import training_chart
from jointid.present.readouts import precision, readouts
from jointid.present.status import compact_status, status_message
from jointid.studies.experiment import run_experiment
from tui.screens.main import MainScreen
from tui.widgets.charts import TorqueChart
from tui.widgets.readouts import ReadoutPanel
from tui.widgets.stepper import Stepper

SIZES = ((20, 5), (250, 80))
"""Smallest and largest terminal (width, height) the storm resizes to."""

PLAIN_KEYS = (
    ["tab"] * 6 + ["shift+tab"] * 3 + ["up", "down"] * 3 + ["left", "right"] * 4
    + ["shift+left", "shift+right"] * 2 + ["enter"] * 4 + ["space", "escape", "escape", "backspace"]
    + list("0123456789") + list("123") * 2 + [".", "-", "e", "r", "r", "c", "g", "a", "k", "x"]
    + ["s", "m", "e", "question_mark", "4"] * 2 + ["p", "l", "d", "n", "u", "k"]
)
"""Single keys, weighted by repetition: navigation, typing, the motion and view keys, letters a
number field must refuse. Not `q` (it quits) nor Ctrl+C."""

MACROS = (
    ("ctrl+p", "escape"), ("ctrl+p", "down", "down", "escape"), ("ctrl+p", "t", "o", "escape"),
    ("escape", "escape", "ctrl+o", "escape"), ("escape", "escape", "ctrl+o", "tab", "escape"),
    ("escape", "escape", "ctrl+s", "escape"),
    # Enter twice in one batch on modal screens (key repeat, SSH batching): the burst guard's case.
    ("escape", "escape", "ctrl+p", "t", "o", "u", "r", "enter", "enter"),
    ("escape", "escape", "ctrl+o", "enter", "enter", "escape", "escape"),
    ("escape", "escape", "p", "tab", "enter", "enter", "escape"),
    ("escape", "escape", "u", "2", "escape"), ("escape", "escape", "n", "escape"),
)
"""Key sequences kept together: the palette, the open and the export dialogs, each left with Escape
(the dialogs' keys belong to the main screen, so two Escapes first leave most views)."""


OPENING = ("s", "m", "e", "l", "d", "question_mark", "p", "ctrl+p", "ctrl+o", "ctrl+s")
"""Each view and dialog opened once (then left with Escape) before the random bursts, so every storm reaches all of
them and its random keys land on any."""


@dataclass
class StormReport:
    """What a storm did, for its assertions and its failure messages."""

    keys: int = 0
    resizes: int = 0
    views: set | None = None


def key_event(key: str) -> events.Key:
    """The Key event Textual's pilot sends for `key` (the same lookups as App._press_keys)."""
    if len(key) == 1 and not key.isalnum():
        key = _character_to_key(key)
    try:
        character = unicodedata.lookup(_get_unicode_name_from_key(REPLACED_KEYS.get(key, key)))
    except KeyError:
        character = key if len(key) == 1 else None
    return events.Key(key, character)


def burst(rng: random.Random) -> list[str]:
    """One burst of keys: a macro now and then, otherwise one to six single keys."""
    if rng.random() < 0.18:
        return list(rng.choice(MACROS))
    return [rng.choice(PLAIN_KEYS) for _ in range(rng.randint(1, 6))]


async def send(pilot, keys: list[str]) -> None:
    """Send a burst without waiting between its keys, then let the app settle."""
    app = pilot.app
    for key in keys:
        event = key_event(key)
        event.set_sender(app)
        app._driver.send_message(event)
    await pilot.pause()


async def back_to_main(pilot) -> MainScreen:
    """Leave every view and dialog with Escape (a running sweep takes one to cancel) and drop any typing."""
    app = pilot.app
    for _ in range(20):
        await app.workers.wait_for_complete()
        await pilot.pause()
        if isinstance(app.screen, MainScreen):
            break
        await pilot.press("escape")
    screen = app.screen
    assert isinstance(screen, MainScreen), f"still on {type(screen).__name__} after 20 Escapes"
    for stepper in screen.query(Stepper):
        if stepper.editing:  # typed but never committed: not part of the settings
            stepper.action_revert()
    await pilot.pause()
    return screen


def assert_shows_the_cores_result(screen: MainScreen) -> None:
    """Readouts, precision notes, status sentence, fields and chart equal the core's for screen.settings."""
    settings = screen.settings
    result = run_experiment(settings)
    panel = screen.query_one(ReadoutPanel)
    assert panel.items == readouts(result), settings
    assert panel.precision == precision(result), settings
    status = screen.query_one("#status")
    shown, full, width = str(status.render()), status_message(result), status.content_region.width
    if shown != full:  # on a compact screen a sentence too long for its rows gives way to the short one
        assert screen.has_class("-compact") and shown == compact_status(result), settings
        assert width <= 0 or len(Content(full).wrap(width)) > status.min_lines, settings
    for stepper in screen.query(Stepper):
        assert stepper.number == getattr(settings, stepper.field)
        assert stepper.value == stepper.steps.format(getattr(settings, stepper.field))
    assert screen.query_one("#training-chart", TorqueChart).data.same_as(training_chart(result))


async def storm(seed: int, key_count: int, resize_chance: float, check_every: int, logs=None) -> StormReport:
    """Press `key_count` random keys from a seeded generator, resizing now and then; check on the way and at the end
    (`logs`: a log or several runs to start on, so that the log's views and keys are stormed too)."""
    rng = random.Random(seed)
    report = StormReport(views={"MainScreen"})
    app = make_app(logs=logs)
    push_screen = app.push_screen

    def push_and_note(screen, *args, **kwargs):
        report.views.add(type(screen).__name__)
        return push_screen(screen, *args, **kwargs)

    app.push_screen = push_and_note  # every screen opened, the palette's and dialogs' too
    opening = [[key, "escape", "escape"] for key in (*(["n", "u"] if logs is not None else []), *OPENING)]
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        next_check = check_every
        while report.keys < key_count:
            keys = opening.pop(0) if opening else burst(rng)
            with time_limit(30):  # a frozen app fails here, naming the keys, instead of hanging
                await send(pilot, keys)
                if rng.random() < resize_chance:
                    size = (rng.randint(SIZES[0][0], SIZES[1][0]), rng.randint(SIZES[0][1], SIZES[1][1]))
                    await pilot.resize_terminal(*size)
                    report.resizes += 1
            report.keys += len(keys)
            assert app.is_running and app._exception is None, (seed, report.keys, keys)
            if report.keys >= next_check and isinstance(app.screen, MainScreen):
                next_check = report.keys + check_every
                await app.workers.wait_for_complete()
                await pilot.pause()
                typing = any(stepper.editing for stepper in app.screen.query(Stepper))
                if not typing and app.screen.logs is None:  # a log's fit is checked by the log tests
                    assert_shows_the_cores_result(app.screen)
        with time_limit(60):
            screen = await back_to_main(pilot)
            if screen.logs is not None:
                await pilot.press("c")  # back to the synthetic experiment, whose result the core can check
                await pilot.pause()
            for size in ((80, 24), (120, 40)):
                await pilot.resize_terminal(*size)
                assert_shows_the_cores_result(screen)
    return report


EVERY_VIEW = {"MainScreen", "SweepScreen", "MatrixScreen", "ResidualScreen", "HelpScreen",
              "CommandPalette", "OpenLogScreen", "ExportScreen", "PhysicsScreen", "LadderScreen", "DesignScreen"}
"""The screens a storm must have opened."""
LOG_VIEWS = {"NotesScreen", "RunsScreen"}
"""The screens a storm started on several runs must also have opened."""


@pytest.fixture
def two_runs(tmp_path):
    """Two runs of the lesson's joint (rich and slow motion, 400 samples each), fitted and pooled."""
    from jointid.cli import main
    from jointid.logs.request import LoadRequest, load_joint_log
    from jointid.model.terms import model_named
    from jointid.studies.runs import fit_runs

    paths = []
    for motion in ("rich", "slow"):
        path = tmp_path / f"{motion}.csv"
        assert main(["simulate", "--motion", motion, "--noise", "0.05", "--samples", "400", "--out", str(path)]) == 0
        paths.append(str(path))
    return fit_runs([load_joint_log(LoadRequest(path)) for path in paths], model_named("plain"))


def test_a_storm_of_600_keys_through_every_view(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # should a dialog ever be submitted, it writes here
    report = asyncio.run(storm(seed=2026, key_count=600, resize_chance=0.12, check_every=100))
    assert report.keys >= 600 and report.resizes >= 15
    assert EVERY_VIEW <= report.views
    assert list(tmp_path.iterdir()) == []


def test_a_storm_of_300_keys_on_several_runs_reaches_the_log_views(tmp_path, monkeypatch, two_runs):
    storm_folder = tmp_path / "storm"
    storm_folder.mkdir()
    monkeypatch.chdir(storm_folder)
    report = asyncio.run(storm(seed=11, key_count=300, resize_chance=0.12, check_every=100, logs=two_runs))
    assert report.keys >= 300
    assert LOG_VIEWS <= report.views, sorted(report.views)
    assert list(storm_folder.iterdir()) == []


@pytest.mark.slow
@pytest.mark.parametrize("seed", [7, 13])
def test_a_storm_of_10000_keys_through_every_view(tmp_path, monkeypatch, seed):
    monkeypatch.chdir(tmp_path)
    report = asyncio.run(storm(seed=seed, key_count=10_000, resize_chance=0.1, check_every=500))
    print(f"seed {seed}: {report.keys} keys, {report.resizes} resizes, views {sorted(report.views)}")
    assert report.keys >= 10_000 and report.resizes >= 200  # a tenth of the bursts; macros make bursts longer
    assert EVERY_VIEW <= report.views
    assert list(tmp_path.iterdir()) == []


def test_a_sweep_result_arriving_while_its_view_is_taken_down_is_dropped():
    """What the first storm found: s, then Escape as the sweep finished. The view's widgets are
    removed before its workers are cancelled; a result delivered in between was shown on widgets
    that were gone, and the app crashed (NoMatches: '#sweep-state'). Here the result is held back
    until the view's widgets are gone, as the storm's timing had it."""

    async def main():
        app = make_app()
        async with app.run_test(size=(80, 24)) as pilot:
            await pilot.pause()
            call_from_thread = app.call_from_thread
            taken_down = []

            def take_down_first(callback, *args, **kwargs):
                screen = getattr(callback, "__self__", None)
                if type(screen).__name__ == "SweepScreen" and callback.__name__ == "_deliver" and not taken_down:
                    taken_down.append(screen)
                    call_from_thread(screen.remove_children)  # as closing the view does, before the cancel
                    call_from_thread(screen.set_focus, None)  # and the focused field goes with it
                return call_from_thread(callback, *args, **kwargs)

            app.call_from_thread = take_down_first
            await pilot.press("s")
            # Until the sweep's worker has reached its final state on the app's loop, Escape means "cancel"
            # rather than "back": wait for that state, not for the thread (the test failed on a loaded machine).
            for worker in [worker for worker in app.workers if worker.group == "sweep"]:
                await worker.wait()
            view = app.screen
            assert type(view).__name__ == "SweepScreen"
            # The result reaches the view through call_from_thread after the thread ends: wait for the view to
            # have taken it (the cap only ends a bug), not for a count of pauses.
            for _ in range(10_000):
                if not view.running:
                    break
                await pilot.pause()
            assert not view.running
            await pilot.press("escape")
            for _ in range(10_000):  # the pop is scheduled by the key's handler: wait for it (the cap only ends a bug)
                if app.screen is not view:
                    break
                await pilot.pause()
            return type(app.screen).__name__, app.is_running, len(taken_down)

    assert asyncio.run(main()) == ("MainScreen", True, 1)
