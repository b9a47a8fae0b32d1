"""The explorer's exit status: 0 after q, non-zero whenever it ended by an exception."""

from __future__ import annotations

import pytest
from textual.app import App

from jointid.cli import main
from jointid.synthetic.settings import DEFAULT_SETTINGS
from tui import entry
from tui.app import JointIdApp
from tui.screens.main import MainScreen


def run_headless(monkeypatch, *keys: str) -> None:
    """Make the app's run() headless, pressing `keys` as a user would (the entry function is unchanged)."""

    async def user(pilot) -> None:
        await pilot.pause()
        await pilot.press(*keys)
        await pilot.pause()

    monkeypatch.setattr(JointIdApp, "run", lambda self, **kwargs: App.run(self, headless=True, auto_pilot=user))


def crash_on_reset(monkeypatch) -> None:
    def reset_that_raises(self) -> None:
        raise RuntimeError("a bug in a key handler")

    monkeypatch.setattr(MainScreen, "action_reset", reset_that_raises)


def test_q_exits_with_status_0(monkeypatch):
    run_headless(monkeypatch, "q")
    assert entry.explore(DEFAULT_SETTINGS) == 0


def test_an_exception_in_a_handler_exits_non_zero(monkeypatch):
    crash_on_reset(monkeypatch)
    run_headless(monkeypatch, "r")
    assert entry.explore(DEFAULT_SETTINGS) == 1


def test_a_quit_while_the_crashed_app_shuts_down_does_not_turn_it_into_success(monkeypatch):
    """Textual's exit() resets the return code to 0; one called from cleanup after a crash hid the crash."""
    crash_on_reset(monkeypatch)
    monkeypatch.setattr(MainScreen, "on_unmount", lambda self: self.app.exit(), raising=False)
    run_headless(monkeypatch, "r")
    assert entry.explore(DEFAULT_SETTINGS) == 1


@pytest.mark.parametrize("keys, status", [(("q",), 0), (("r",), 1)])
def test_the_command_line_passes_the_explorers_status_on(monkeypatch, keys, status):
    crash_on_reset(monkeypatch)
    run_headless(monkeypatch, *keys)
    assert main([]) == status


def test_the_named_statuses_are_the_numbers_shells_and_the_docs_use():
    from jointid.cli.exit_status import ExitStatus

    assert [(status.name, int(status)) for status in ExitStatus] == [
        ("SUCCESS", 0), ("ERROR", 1), ("USER_ERROR", 2), ("INTERRUPTED", 130)]
    with pytest.raises(SystemExit) as refused:  # argparse's own errors exit from the parser
        main(["fit", "--noise", "-1"])
    assert refused.value.code is ExitStatus.USER_ERROR
    assert main(["fit", "--csv", "/no/such/log.csv"]) is ExitStatus.USER_ERROR
    assert main(["torque", "--q", "60", "--deg", "--qd", "-2", "--qdd", "3"]) is ExitStatus.SUCCESS
