"""Paths typed into the explorer's dialogs: whatever they name, a notification, never a crash or a hang.

Ctrl+S into a folder that cannot be (`~nosuchuser/...`, a name longer than the
system allows) and Ctrl+O on a named pipe, as a log or as a bag, each end in one
notification with the explorer still running; waits are on the app's messages.
"""

from __future__ import annotations

import os

import pytest
from support.bursts import MessageWatch, with_app
from test_key_bursts import main_screen
from textual.widgets import Input

from tui.screens.export import ExportScreen

needs_fifos = pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes on this system")


async def notified(app, watch: MessageWatch, title: str):
    """The first notification with `title`, once it is shown."""
    await watch.until(app, lambda: any(n.title == title for n in app._notifications), f"a {title!r} notification")
    return next(n for n in app._notifications if n.title == title)


async def export_into(pilot, app, folder: str) -> None:
    await pilot.press("ctrl+s")
    assert isinstance(app.screen, ExportScreen)
    app.screen.query_one(Input).value = folder
    await pilot.press("enter")


@with_app
async def test_export_under_the_home_of_no_such_user_is_a_notification(pilot, app, watch):
    await export_into(pilot, app, "~nosuchuser-of-jointid/exports")
    note = await notified(app, watch, "Nothing exported")
    assert note.message == "~nosuchuser-of-jointid/exports: no such user, so no home folder to expand ~ to"
    assert note.severity == "error" and app.screen is main_screen(app)


@with_app
async def test_export_into_a_name_too_long_for_the_system_is_a_notification(pilot, app, watch, tmp_path):
    folder = tmp_path / ("x" * 300)  # file names stop at 255 bytes
    await export_into(pilot, app, str(folder))
    note = await notified(app, watch, "Nothing exported")
    assert note.message == f"{folder}: cannot use this folder: File name too long"
    assert app.screen is main_screen(app) and os.listdir(tmp_path) == []


@with_app
async def test_export_of_a_name_too_long_for_the_system_is_a_notification(pilot, app, watch, tmp_path):
    main_screen(app).export_content = lambda: ("y" * 300, {})  # a log's name of 300 bytes gives such a stem
    await export_into(pilot, app, str(tmp_path))
    note = await notified(app, watch, "Nothing exported")
    assert note.message.endswith("cannot write: File name too long")
    assert app.screen is main_screen(app) and os.listdir(tmp_path) == []


async def open_log(pilot, app, path) -> None:
    await pilot.press("ctrl+o")
    app.screen.query_one("#open-path", Input).value = str(path)
    await pilot.press("enter")


@needs_fifos
@pytest.mark.parametrize("name", ["pipe.csv", "pipe.bag", "pipe.mcap"])
@with_app
async def test_ctrl_o_on_a_named_pipe_is_a_notification(pilot, app, watch, tmp_path, name):
    if not name.endswith(".csv"):
        pytest.importorskip("rosbags")
    path = tmp_path / name
    os.mkfifo(path)  # nothing ever writes to it: reading it would wait for ever
    await open_log(pilot, app, path)
    note = await notified(app, watch, "Log not loaded")
    assert note.message == f"{path}: cannot read: a named pipe (FIFO), not a regular file"
    assert main_screen(app).logs is None


@needs_fifos
@with_app
async def test_ctrl_o_on_a_bag_folder_holding_a_named_pipe_is_a_notification(pilot, app, watch, tmp_path):
    pytest.importorskip("rosbags")
    folder = tmp_path / "arm"
    folder.mkdir()
    (folder / "metadata.yaml").write_text("rosbag2_bagfile_information:\n  relative_file_paths: [arm_0.db3]\n")
    os.mkfifo(folder / "arm_0.db3")
    await open_log(pilot, app, folder)
    note = await notified(app, watch, "Log not loaded")
    assert note.message == f"{folder}, file arm_0.db3: cannot read: a named pipe (FIFO), not a regular file"


def test_an_export_killed_between_its_two_files_leaves_its_name_to_the_next_one(tmp_path):
    """kill -9 after the JSON's link left stem.json without stem.svg; the next export removes it and takes the name."""
    import subprocess
    import sys

    from jointid.files import TEMPORARY_SUFFIX
    from tui.screens.export import write_export

    done = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True,
                          check=True)
    dead = done.stdout.strip()  # a process id that no longer runs, as the killed writer's
    for member, text in enumerate(("{}", "<svg/>")):  # the pair's temporaries, JSON first
        (tmp_path / f".jointid.{dead}-0123abcd-{member}{TEMPORARY_SUFFIX}").write_text(text)
    os.link(tmp_path / f".jointid.{dead}-0123abcd-0{TEMPORARY_SUFFIX}", tmp_path / "stem.json")  # its one link
    paths = write_export(tmp_path, "stem", {"fit": 1}, "<svg>new</svg>")
    assert [path.name for path in paths] == ["stem.json", "stem.svg"]
    assert sorted(os.listdir(tmp_path)) == ["stem.json", "stem.svg"]
    assert (tmp_path / "stem.svg").read_text() == "<svg>new</svg>"
