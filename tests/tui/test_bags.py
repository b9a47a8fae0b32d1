"""The explorer opens ROS bags like CSV logs: Ctrl+O, the joint picker, progress, Escape, bad bags notified."""

from __future__ import annotations

import json
import threading
import time

import numpy as np
import pytest

pytest.importorskip("rosbags")

from support.bag_support import bag_path, two_joints, write_joint_bag, write_mismatched_bag  # noqa: E402
from support.tui_support import displayed_readouts, make_app  # noqa: E402
from test_logs import SIZE, main_screen, synchronous  # noqa: E402
from textual.widgets import Input, OptionList  # noqa: E402

from jointid.cli import main  # noqa: E402
from jointid.logs import bag as bag_module  # noqa: E402
from jointid.studies.log_fit import LoadRequest  # noqa: E402
from tui.screens.bag_joint import BagJointScreen  # noqa: E402
from tui.screens.main import MainScreen  # noqa: E402


@pytest.fixture(scope="module")
def bags(tmp_path_factory):
    folder = tmp_path_factory.mktemp("tui-bags")
    t = np.arange(2000) / 500.0
    good = write_joint_bag(bag_path(folder, "arm", "mcap"), "mcap", t, two_joints(t))
    corrupt = folder / "corrupt.bag"
    corrupt.write_bytes(b"#ROSBAG V2.0\n" + bytes(range(256)) * 4)
    no_effort = write_joint_bag(bag_path(folder, "noeffort", "sqlite3"), "sqlite3", t, two_joints(t), effort=False)
    mismatched = write_mismatched_bag(folder, "ros1", "effort", 1)
    return {"good": good, "corrupt": corrupt, "no effort": no_effort, "mismatched": mismatched}


async def settle(pilot, until=None):
    """Wait for the explorer's own workers (the open dialog's folder tree keeps one running for ever)."""
    for _ in range(400):
        busy = [w for w in pilot.app.workers if w.group in ("bag-survey", "log-load") and not w.is_finished]
        if not busy and (until is None or until()):
            break
        await pilot.pause(0.02)
    await pilot.pause()


@synchronous
async def test_ctrl_o_on_a_bag_picks_a_joint_and_fits_it_as_the_command_line_does(bags, capsys):
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await pilot.press("ctrl+o")
        field = app.screen.query_one("#open-path", Input)
        field.value = str(bags["good"])
        await pilot.press("enter")
        await settle(pilot, lambda: app.screen.query_one(OptionList).option_count)
        assert isinstance(app.screen, BagJointScreen)
        options = app.screen.query_one(OptionList)
        assert [str(options.get_option_at_index(i).prompt) for i in range(options.option_count)] == [
            "shoulder: position, velocity, effort (2000 messages)",
            "elbow: position, velocity, effort (2000 messages)",
        ]
        await pilot.press("enter")
        await settle(pilot, lambda: isinstance(app.screen, MainScreen))
        screen = main_screen(app)
        assert isinstance(app.screen, MainScreen) and screen.logs is not None
        assert screen.logs.training.read_brief == "'shoulder', 2000 messages"
        estimate, model = screen.logs.result.estimate, screen.settings.model
    # Ctrl+O fits a new log with the log defaults, as `jointid fit --bag` does without --model.
    assert model == "coulomb+bias"
    capsys.readouterr()
    assert main(["fit", "--bag", str(bags["good"]), "--joint", "shoulder", "--json"]) == 0
    expected = json.loads(capsys.readouterr().out)["estimate"]
    assert list(expected) == ["I", "h", "B", "Fc", "tau0"]
    assert [float(v) for v in estimate] == [expected[name] for name in expected]


@synchronous
async def test_the_picker_on_a_corrupt_bag_notifies_and_closes(bags):
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await pilot.press("ctrl+o")
        app.screen.query_one("#open-path", Input).value = str(bags["corrupt"])
        await pilot.press("enter")
        await settle(pilot, lambda: not isinstance(app.screen, BagJointScreen))
        assert not isinstance(app.screen, BagJointScreen)
        (note,) = app._notifications
        assert note.severity == "error" and "corrupt.bag: cannot be read as a ROS 1 bag" in note.message
        await pilot.press("escape")
        assert isinstance(app.screen, MainScreen)


@pytest.mark.parametrize("case, joint", [("corrupt", "shoulder"), ("no effort", "shoulder"), ("good", "wrist"),
                                         ("mismatched", "shoulder")])
@synchronous
async def test_a_bad_bag_is_one_notification_and_nothing_on_screen_changes(bags, capsys, case, joint):
    capsys.readouterr()
    assert main(["fit", "--bag", str(bags[case]), "--joint", joint]) == 2
    line = capsys.readouterr().err.strip().removeprefix("jointid: ")
    if case == "mismatched":  # not "no effort ... (the arrays are empty)": the message and field at fault
        assert ("1 of 100 messages on /joint_states (first: message 41, effort has 1 value for 2 joint names)"
                in line), line
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        before = displayed_readouts(app.screen)
        app.screen.start_loading(LoadRequest(str(bags[case]), joint=joint))
        await settle(pilot)
        assert isinstance(app.screen, MainScreen) and app.screen.logs is None
        assert displayed_readouts(app.screen) == before
        assert [(n.message, n.severity) for n in app._notifications] == [(line, "error")]


@synchronous
async def test_escape_cancels_loading_a_bag(bags, monkeypatch):
    monkeypatch.setattr(bag_module, "BLOCK", 1)  # one message per block: the cancel check runs after each
    # The reading waits after its first block until the cancel check says stop (Escape), however loaded the
    # machine: without that the whole bag could be read before the key arrived.
    pause = threading.Event()  # never set: its wait is the poll interval

    def progress_waits_for_cancel(real_scan_init):
        def init(self, path, reader, connections, consume, progress=None, cancel=None, limit=None):
            def waiting_cancel():
                if cancel is None:
                    return False
                deadline = time.monotonic() + 30
                while not cancel() and time.monotonic() < deadline:
                    pause.wait(0.01)
                return cancel()
            real_scan_init(self, path, reader, connections, consume, progress, waiting_cancel, limit)
        return init

    monkeypatch.setattr(bag_module._Scan, "__init__", progress_waits_for_cancel(bag_module._Scan.__init__))
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        before = displayed_readouts(app.screen)
        app.screen.start_loading(LoadRequest(str(bags["good"]), joint="shoulder"))
        await pilot.pause()
        assert type(app.screen).__name__ == "LoadingScreen"
        await pilot.press("escape")
        await settle(pilot)
        assert isinstance(app.screen, MainScreen) and app.screen.logs is None
        assert displayed_readouts(app.screen) == before
        assert [n.message for n in app._notifications] == ["Loading cancelled; nothing changed."]


async def _wait_in_thread(event: threading.Event) -> None:
    """Wait for an event set by the load worker without blocking the app's loop."""
    import asyncio

    assert await asyncio.to_thread(event.wait, 30), "the load worker never got there"


@synchronous
async def test_escape_during_the_fit_drops_its_result(bags, monkeypatch):
    # The fit cannot stop part-way; an Escape while it runs must still leave the explorer as it was.
    from jointid.studies import log_fit

    fitting, release = threading.Event(), threading.Event()
    real_fit = log_fit.fit_logs

    def held_fit(*args, **kwargs):
        fitting.set()
        release.wait(30)
        return real_fit(*args, **kwargs)

    monkeypatch.setattr(log_fit, "fit_logs", held_fit)
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        before = displayed_readouts(app.screen)
        app.screen.start_loading(LoadRequest(str(bags["good"]), joint="shoulder"))
        await _wait_in_thread(fitting)
        await pilot.pause()
        assert type(app.screen).__name__ == "LoadingScreen"
        await pilot.press("escape")
        hint = str(app.screen.query_one("#load-hint").render())
        assert str(app.screen.query_one("Label").render()).startswith("Loading arm")
        assert "the fit cannot stop part-way; its result will be dropped" in hint, hint
        release.set()
        await settle(pilot)
        assert isinstance(app.screen, MainScreen) and app.screen.logs is None
        assert displayed_readouts(app.screen) == before
        assert [(n.message, n.severity) for n in app._notifications] == [
            ("Loading cancelled; nothing changed.", "warning")]


@synchronous
async def test_escape_after_the_reading_starts_no_fit(bags, monkeypatch):
    from jointid.studies import log_fit

    read, release, fits = threading.Event(), threading.Event(), []
    real_load = log_fit.load_joint_log

    def held_load(*args, **kwargs):
        log = real_load(*args, **kwargs)
        read.set()
        release.wait(30)
        return log

    monkeypatch.setattr(log_fit, "load_joint_log", held_load)
    monkeypatch.setattr(log_fit, "fit_logs", lambda *args, **kwargs: fits.append(args))
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        app.screen.start_loading(LoadRequest(str(bags["good"]), joint="shoulder"))
        await _wait_in_thread(read)
        await pilot.pause()
        await pilot.press("escape")
        release.set()
        await settle(pilot)
        assert fits == [] and app.screen.logs is None
        assert [n.message for n in app._notifications] == ["Loading cancelled; nothing changed."]


@synchronous
async def test_the_picker_lists_a_bag_with_mismatched_arrays_and_loading_it_names_the_topic_and_count(bags):
    """The picker refused the whole bag over one message whose effort array did not match its names."""
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await pilot.press("ctrl+o")
        app.screen.query_one("#open-path", Input).value = str(bags["mismatched"])
        await pilot.press("enter")
        await settle(pilot, lambda: isinstance(app.screen, BagJointScreen)
                     and app.screen.query_one(OptionList).option_count)
        options = app.screen.query_one(OptionList)
        lines = [str(options.get_option_at_index(i).prompt) for i in range(options.option_count)]
        assert lines == ["shoulder: position, velocity, effort (99 messages)",
                         "elbow: position, velocity, effort (99 messages)"]
        await pilot.press("enter")
        await settle(pilot, lambda: any(n.severity == "error" for n in app._notifications))
        (note,) = [n for n in app._notifications if n.severity == "error"]
        assert "1 of 100 messages on /joint_states (first: message 41, effort has 1 value" in note.message
        assert main_screen(app).logs is None
