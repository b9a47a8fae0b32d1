"""The Ctrl+O dialog keeps what was typed: a file that cannot be used leaves it open with its path, and its tree
hides dot-folders as file pickers do (issue 24, items 5 and 10).

Keys are delivered as one batch (support.bursts.send_burst); waits are on the app's own messages.
"""

from __future__ import annotations

import pytest
from support.bursts import MessageWatch, send_burst, with_app
from support.log_files import CORPUS
from test_key_bursts import main_screen
from textual.widgets import Input

from jointid.cli import main
from tui.screens.loading import LoadingScreen
from tui.screens.open_log import LogTree, OpenLogScreen


async def failed(app, watch: MessageWatch) -> None:
    """Wait until the load's failure is said and its progress dialog is gone."""
    await watch.until(app, lambda: any(n.title == "Log not loaded" for n in app._notifications)
                      and not any(isinstance(s, LoadingScreen) for s in app.screen_stack), "the failed load")


async def open_dialog(pilot, app) -> OpenLogScreen:
    await pilot.press("ctrl+o")
    assert isinstance(app.screen, OpenLogScreen)
    return app.screen



@pytest.mark.parametrize("name", ["nan.csv", "empty.bag", "header_only.csv"])
@with_app
async def test_a_file_that_cannot_be_loaded_leaves_the_open_dialog_with_its_path(pilot, app, watch, tmp_path, name):
    """Every failure, CSV or bag, read or refused: the dialog stays with the typed path and keeps the keys."""
    path = tmp_path / name
    if name == "nan.csv":
        path.write_bytes(CORPUS["nan.csv"].encode("latin-1"))
    elif name == "empty.bag":
        pytest.importorskip("rosbags")
        path.write_bytes(b"")
    else:
        path.write_text("t,q,tau\n")  # read, then refused: no rows to fit
    dialog = await open_dialog(pilot, app)
    field = dialog.query_one("#open-path", Input)
    field.value = str(path)
    field.cursor_position = len(field.value)
    send_burst(app, "enter")
    await failed(app, watch)
    assert app.screen is dialog and field.value == str(path) and field.has_focus
    # Typing goes on into the path; it runs no command of the main screen (2 and s would).
    send_burst(app, "2", "s")
    await watch.until(app, lambda: field.value == f"{path}2s", "the typing to reach the path field")
    assert app.screen is dialog and main_screen(app).logs is None


@with_app
async def test_a_file_chosen_in_the_tree_that_cannot_be_loaded_leaves_it_named_in_the_path(pilot, app, watch, tmp_path):
    path = tmp_path / "nan.csv"
    path.write_bytes(CORPUS["nan.csv"].encode("latin-1"))
    dialog = await open_dialog(pilot, app)
    tree = dialog.query_one(LogTree)
    tree.post_message(LogTree.FileSelected(tree.root, path))
    await failed(app, watch)
    assert app.screen is dialog and dialog.query_one("#open-path", Input).value == str(path)


@with_app
async def test_a_log_that_loads_closes_the_dialog_and_escape_there_still_cancels(pilot, app, watch, tmp_path, capsys):
    path = tmp_path / "rich.csv"
    assert main(["simulate", "--out", str(path), "--noise", "0.05", "--samples", "400"]) == 0
    capsys.readouterr()
    dialog = await open_dialog(pilot, app)
    dialog.query_one("#open-path", Input).value = str(path)
    send_burst(app, "enter")
    await watch.until(app, lambda: main_screen(app).logs is not None and app.screen is main_screen(app),
                      "the log to load and both dialogs to close")
    assert len(app.screen_stack) == 1
    dialog = await open_dialog(pilot, app)
    send_burst(app, "escape")
    await watch.until(app, lambda: app.screen is main_screen(app), "Escape to close the dialog")


@with_app
async def test_the_tree_hides_dot_folders_unless_the_typed_path_goes_there(pilot, app, watch, tmp_path):
    for name in (".git", ".venv", "logs"):
        (tmp_path / name).mkdir()
    (tmp_path / ".venv" / "inside.csv").write_text("t,q,tau\n")
    (tmp_path / "run.csv").write_text("t,q,tau\n")
    dialog = await open_dialog(pilot, app)
    tree = dialog.query_one(LogTree)

    def listed() -> list[str]:
        return sorted(str(node.label) for node in tree.root.children)

    field = dialog.query_one("#open-path", Input)
    field.value = str(tmp_path)
    send_burst(app, "enter")
    await watch.until(app, lambda: listed() == ["logs", "run.csv"], "the folder's visible entries")
    field.value = str(tmp_path / ".venv")
    send_burst(app, "enter")
    await watch.until(app, lambda: listed() == ["inside.csv"], "the hidden folder typed, listed")
