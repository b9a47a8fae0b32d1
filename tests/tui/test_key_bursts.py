"""Every modal screen under key bursts: Enter Enter delivered as one batch closes a dialog once, never the app.

Key repeat and SSH batching hand the app several keys before it handles the
first. Each test queues its burst at once (support.bursts.send_burst) and waits
for the dialog's own message pump to stop, which it does only after handling
everything queued for it; a crash ends the wait with the app's exception.
"""

from __future__ import annotations

import threading

import numpy as np
import pytest
from support.bursts import closed, send_burst, with_app
from textual.command import CommandInput, CommandList, CommandPalette
from textual.widgets import Input, OptionList

from jointid.cli import main
from tui.palette import TOUR
from tui.screens.export import ExportScreen
from tui.screens.main import MainScreen
from tui.screens.open_log import OpenLogScreen


def main_screen(app) -> MainScreen:
    """The explorer's main screen, under any dialog."""
    return next(s for s in app.screen_stack if isinstance(s, MainScreen))


@pytest.mark.parametrize("keys", [("enter", "enter"), ("enter", "enter", "enter", "enter")])
@with_app
async def test_enter_enter_in_the_command_palette_runs_the_command_once_and_closes_it(pilot, app, watch, keys):
    await pilot.press("ctrl+p")
    palette = app.screen
    assert isinstance(palette, CommandPalette)
    palette.query_one(CommandInput).value = "Tour 2:"
    commands = palette.query_one(CommandList)
    await watch.until(app, lambda: commands.option_count == 1, "the palette to find the tour stop")
    send_burst(app, *keys)
    await closed(app, watch, palette)
    assert app.screen is main_screen(app) and len(app.screen_stack) == 1
    await watch.until(app, lambda: main_screen(app).settings == TOUR[1], "the tour stop to apply")


@with_app
async def test_enter_enter_in_the_export_dialog_writes_one_pair(pilot, app, watch, tmp_path):
    await pilot.press("ctrl+s")
    dialog = app.screen
    assert isinstance(dialog, ExportScreen)
    dialog.query_one(Input).value = str(tmp_path)
    send_burst(app, "enter", "enter")
    await closed(app, watch, dialog)
    await watch.until(app, lambda: any(n.title == "Exported" for n in app._notifications), "the export")
    assert app.screen is main_screen(app)
    assert sorted(path.suffix for path in tmp_path.iterdir()) == [".json", ".svg"]


@pytest.fixture
def log_file(tmp_path, capsys):
    path = tmp_path / "rich.csv"
    assert main(["simulate", "--out", str(path), "--noise", "0.05", "--samples", "400"]) == 0
    capsys.readouterr()
    return path


@with_app
async def test_enter_enter_in_the_open_dialog_loads_the_log_once(pilot, app, watch, log_file):
    await pilot.press("ctrl+o")
    dialog = app.screen
    assert isinstance(dialog, OpenLogScreen)
    dialog.query_one("#open-path", Input).value = str(log_file)
    send_burst(app, "enter", "enter")
    await closed(app, watch, dialog)
    await watch.until(app, lambda: main_screen(app).logs is not None and app.screen is main_screen(app),
                      "the log to load")
    assert len(app.screen_stack) == 1


# The bag joint picker ---------------------------------------------------------------------------------------


@pytest.fixture
def bag(tmp_path):
    pytest.importorskip("rosbags")
    from support.bag_support import bag_path, two_joints, write_joint_bag

    t = np.arange(400) / 100.0
    return write_joint_bag(bag_path(tmp_path, "arm", "mcap"), "mcap", t, two_joints(t))


async def open_picker(pilot, app, watch, path):
    """Ctrl+O on a bag: the joint picker (its list filled once the bag is surveyed)."""
    await pilot.press("ctrl+o")
    app.screen.query_one("#open-path", Input).value = str(path)
    await pilot.press("enter")
    picker = app.screen
    assert type(picker).__name__ == "BagJointScreen"
    return picker


@with_app
async def test_enter_enter_in_the_joint_picker_loads_the_joint_once(pilot, app, watch, bag):
    picker = await open_picker(pilot, app, watch, bag)
    await watch.until(app, lambda: picker.query_one(OptionList).option_count == 2, "the joints to be listed")
    opener = app.screen_stack[-2]
    send_burst(app, "enter", "enter")
    await closed(app, watch, picker)
    await closed(app, watch, opener)
    await watch.until(app, lambda: main_screen(app).logs is not None and app.screen is main_screen(app),
                      "the joint to load")
    assert main_screen(app).logs.training.read_brief.startswith("'shoulder'")


@with_app
async def test_a_survey_failing_under_the_command_palette_closes_the_picker_once(pilot, app, watch, tmp_path,
                                                                               monkeypatch):
    """The survey's failure dismissed the covered picker: stock Textual closed the palette instead, then the picker
    again on Escape, calling its result callback twice (InvalidStateError)."""
    pytest.importorskip("rosbags")
    from jointid.logs import bag as bag_module

    corrupt = tmp_path / "corrupt.bag"
    corrupt.write_bytes(b"#ROSBAG V2.0\n" + bytes(range(256)) * 4)
    release = threading.Event()
    real_bag_info = bag_module.bag_info

    def held_bag_info(*args, **kwargs):
        release.wait(60)  # the survey ends only once the palette is open over the picker
        return real_bag_info(*args, **kwargs)

    monkeypatch.setattr(bag_module, "bag_info", held_bag_info)
    picker = await open_picker(pilot, app, watch, corrupt)
    opener = app.screen_stack[-2]
    await pilot.press("ctrl+p")
    palette = app.screen
    assert isinstance(palette, CommandPalette)
    release.set()
    await closed(app, watch, picker)
    assert app.screen is opener and not palette.is_running
    assert [n.title for n in app._notifications] == ["Log not loaded"]
    send_burst(app, "escape", "escape")
    await closed(app, watch, opener)
    assert app.screen_stack == [main_screen(app)]


async def typed_in_burst(app, watch, field: Input, keys: tuple[str, ...]) -> str:
    """The field's text after `keys` arrive as one batch: each key reaches the app once from the terminal, and the
    ones the field does not type (backspace, arrows) once more, bubbled back up for the app to run as a binding."""
    from textual import events

    field.value = ""
    watch.record()
    send_burst(app, *keys)
    bubbled = sum(1 for key in keys if len(key) > 1)
    await watch.until(app, lambda: watch.count(app, events.Key) >= len(keys) + bubbled, "the burst to be handled")
    return field.value


@with_app
async def test_the_burst_guard_leaves_a_burst_of_typing_as_textual_delivers_it(pilot, app, watch):
    """Typed characters arrive in order; a bound key (backspace) runs after the characters typed after it in the
    same burst, with the guard as without it: Textual's order (textual#6605), not the guard's."""
    from tui.third_party.adapter import BurstGuard

    await pilot.press("ctrl+o")
    dialog = app.screen
    assert isinstance(dialog, OpenLogScreen) and BurstGuard._stock  # the guard is installed
    field = dialog.query_one("#open-path", Input)
    field.focus()
    keys = ("a", "b", "backspace", "c")
    assert await typed_in_burst(app, watch, field, ("x", "y", "z")) == "xyz"
    guarded = await typed_in_burst(app, watch, field, keys)
    BurstGuard.uninstall()
    try:
        stock = await typed_in_burst(app, watch, field, keys)
    finally:
        BurstGuard.install()
    assert guarded == stock == "ab"  # in order it would be "ac": c is typed before backspace's binding runs
