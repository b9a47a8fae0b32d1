"""Small things a user meets: where Tab stops, the dialogs' keys, empty paths, notifications, the palette."""

from __future__ import annotations

import asyncio

import pytest
from support.tui_support import make_app
from textual.widgets import Input
from textual.widgets._toast import Toast

from jointid.cli import main
from tui.screens.export import ExportScreen
from tui.screens.main import MainScreen
from tui.screens.open_log import OpenLogScreen
from tui.widgets.footer import KeyEntry, KeyFooter, footer_line
from tui.widgets.readouts import ReadoutPanel


def run(scenario, size=(80, 24), notifications=False):
    async def go():
        app = make_app()
        async with app.run_test(size=size, notifications=notifications) as pilot:
            await pilot.pause()
            return await scenario(pilot, app)

    return asyncio.run(go())


@pytest.fixture
def logs(tmp_path):
    train, test = tmp_path / "train.csv", tmp_path / "test.csv"
    assert main(["simulate", "--noise", "0.1", "--samples", "300", "--out", str(train)]) == 0
    assert main(["simulate", "--motion", "test", "--samples", "100", "--out", str(test)]) == 0
    return train, test


async def load_logs(pilot, train, test) -> None:
    from jointid.studies.log_fit import HELDOUT, LoadRequest

    for path, role in ((train, "training"), (test, HELDOUT)):
        pilot.app.screen.start_loading(LoadRequest(str(path), role, False))
        await pilot.app.workers.wait_for_complete()
        await pilot.pause()


# --- Tab ----------------------------------------------------------------------------


async def tab_stops(pilot, app) -> list[str]:
    """The widgets Tab visits, in order, from the motion list round to it again."""
    stops = []
    app.screen.query_one("#motion").focus()
    await pilot.pause()
    for _ in range(12):
        stops.append(type(app.focused).__name__ + (f"#{app.focused.id}" if app.focused.id else ""))
        await pilot.press("tab")
        await pilot.pause()
        if app.focused.id == "motion":
            break
    return stops


@pytest.mark.parametrize("size", [(80, 24), (120, 40)])
def test_tab_visits_the_controls_only_where_every_readout_is_on_screen(size):
    """Tab stopped at the readout panel, which showed it only by a faint tint."""
    stops = run(tab_stops, size)
    assert stops == ["ChoiceList#motion", "Stepper#noise", "Stepper#samples", "Stepper#seed", "ActionButton#reset"]


def test_on_a_terminal_too_short_for_every_readout_tab_scrolls_them_into_view():
    async def scenario(pilot, app):
        side = app.screen.query_one("#side")
        stops = await tab_stops(pilot, app)
        assert side.max_scroll_y > 0
        panel = app.screen.query_one(ReadoutPanel)
        panel.focus()
        await pilot.pause()
        return stops, side.scroll_y, app.focused is panel

    stops, scrolled, focused = run(scenario, (75, 22))
    assert stops[-1] == "ReadoutPanel#readouts" and scrolled > 0 and focused


# --- the dialogs ------------------------------------------------------------------------


@pytest.mark.parametrize("key, dialog", [("ctrl+o", OpenLogScreen), ("ctrl+s", ExportScreen)])
def test_the_dialogs_show_their_own_keys_over_the_explorers_footer(key, dialog):
    async def scenario(pilot, app):
        await pilot.press(key)
        await pilot.pause()
        assert isinstance(app.screen, dialog)
        footer = app.screen.query_one(KeyFooter)
        return footer.text, footer.region.bottom, app.size.height

    text, bottom, height = run(scenario)
    assert "Cancel" in text and "Sweep" not in text and "Quit" not in text
    assert bottom == height  # on the last row, over the main screen's footer


@pytest.mark.parametrize("typed, phrase", [("", "Type the path of a CSV log"), ("no/such.csv", "no/such.csv: no such file")])
def test_an_empty_or_missing_path_is_said_in_the_open_dialog_which_stays(typed, phrase):
    """An empty path gave ': cannot open: No such file or directory' after the dialog had closed."""

    async def scenario(pilot, app):
        await pilot.press("ctrl+o")
        await pilot.pause()
        app.screen.query_one("#open-path", Input).value = typed
        await pilot.press("enter")
        await pilot.pause()
        return type(app.screen), [n.message for n in app._notifications]

    screen, messages = run(scenario)
    assert screen is OpenLogScreen
    assert len(messages) == 1 and phrase in messages[0] and "cannot open" not in messages[0]


# --- notifications -----------------------------------------------------------------------


@pytest.mark.parametrize("size", [(80, 24), (120, 40)])
def test_notifications_leave_the_status_sentence_visible(size):
    async def scenario(pilot, app):
        app.screen.notify("A message long enough to wrap onto a second line of its toast.", title="Note")
        await pilot.pause(0.1)
        toasts = [toast.region for toast in app.screen.query(Toast)]
        return toasts, app.screen.query_one("#status").region

    toasts, status = run(scenario, size, notifications=True)
    assert toasts and not any(toast.overlaps(status) for toast in toasts)


# --- the palette and the footer in log mode ---------------------------------------------------


def palette_titles(app) -> set[str]:
    return {command.title for command in app.get_system_commands(app.screen)}


def test_the_palette_offers_close_log_only_with_a_log_and_the_synthetic_views_only_without(logs):
    async def scenario(pilot, app):
        synthetic = palette_titles(app)
        await load_logs(pilot, *logs)
        with_log = palette_titles(app)
        await pilot.press("s")
        await pilot.pause()
        return synthetic, with_log, type(app.screen), [n.message for n in app._notifications]

    synthetic, with_log, screen, messages = run(scenario)
    assert "Close log" not in synthetic and {"Sweep", "Matrix"} <= synthetic
    assert "Close log" in with_log and not {"Sweep", "Matrix"} & with_log
    # The key still says why, rather than doing nothing.
    assert screen is MainScreen and any("seed sweep needs a synthetic experiment" in m for m in messages)


def test_with_a_log_at_80_columns_the_footer_keeps_close_log_and_export(logs):
    async def scenario(pilot, app):
        await load_logs(pilot, *logs)
        return app.screen.query_one(KeyFooter).text, app.screen.query_one("#status").size.height

    text, status_rows = run(scenario)
    # The sweep and the matrix do not apply to a log: off, so left out of a tight footer (r resets the log's fit,
    # out of the footer); Quit
    # is the one working key a tight footer drops.
    for entry in ("Motion", "? Help", "e l d Views", "Physics", "Open log", "Close log", "Export"):
        assert entry in text
    # Ctrl+O fits the log defaults' five terms, as `jointid --csv` does: their sentence may take one row more than
    # the plain model's four.
    assert "Sweep" not in text and "Reset" not in text and "…" not in text and status_rows in (4, 5)


def test_the_footer_leaves_out_keys_that_are_off_before_cutting_keys_that_work():
    entries = (KeyEntry("a", "Alpha"), KeyEntry("b", "Bravo", enabled=False), KeyEntry("c", "Charlie"),
               KeyEntry("d", "Delta", enabled=False), KeyEntry("e", "Echo"))
    assert footer_line(entries, None, 60).plain.split() == ["a", "Alpha", "b", "Bravo", "c", "Charlie",
                                                             "d", "Delta", "e", "Echo"]
    assert footer_line(entries, None, 24).plain.split() == ["a", "Alpha", "c", "Charlie", "e", "Echo"]
    assert footer_line(entries, None, 12).plain.split() == ["a", "Alpha", "…"]
