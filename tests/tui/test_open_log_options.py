"""The explorer reads a log as the command line does (issue 33, item 7): Ctrl+O fits a new log with the log
defaults, and its dialog's zero, clockwise, degrees and a current's gear, kt and efficiency are the command line's
flags, at 80x24 (the size `jointid serve` students get), with keys only.

Every fit the explorer shows is compared with the library's `jointid.fit_log` of the same file and options, which
is what `jointid fit --csv` computes (tests/core checks the library against independent references); keys are
pressed as a user would, and waits are on the app's own messages.
"""

from __future__ import annotations

import numpy as np
import pytest
from support.bursts import closed, send_burst, with_app
from support.real_logs import REAL_LOGS, needs_real_logs
from textual.widgets import Input

import jointid
from jointid.cli import main
from jointid.logs.conventions import ZEROS
from jointid.options import LOG_MODEL, VOLTAGE_LOG_MODEL, default_log_model
from jointid.present.text import format_number
from tui.screens.loading import LoadingScreen
from tui.screens.main import MainScreen
from tui.screens.open_log import OpenLogScreen
from tui.widgets.direct_controls import ChoiceList
from tui.widgets.stepper import Stepper

SIZE = (80, 24)
"""The smallest terminal the explorer supports, and a browser's default under `jointid serve`."""


at_80x24 = with_app(size=SIZE, notifications=True)
"""Run an async test body as test(pilot, app, watch, **fixtures) on a fresh explorer at 80x24."""


def main_screen(app) -> MainScreen:
    """The explorer's main screen, under any dialog."""
    return next(s for s in app.screen_stack if isinstance(s, MainScreen))


async def open_dialog(pilot, app) -> OpenLogScreen:
    """Ctrl+O: the open dialog, its path field focused."""
    await pilot.press("ctrl+o")
    assert isinstance(app.screen, OpenLogScreen)
    return app.screen


async def loaded(app, watch, what: str = "the log to load") -> None:
    """Wait until a load ended (shown, or refused with a notification) and its dialogs are gone."""
    await watch.until(app, lambda: app.screen is main_screen(app)
                      and not any(worker.is_running for worker in app.workers if worker.group == "log-load"), what)


async def choose(pilot, dialog: OpenLogScreen, option_set: str, steps: int) -> None:
    """Move to a radio set with Tab from the path field, step down to an option and press it, as a user would."""
    order = ("open-role", "open-effort", "open-zero")
    for _ in range(order.index(option_set) + 1):
        await pilot.press("tab")
    assert dialog.focused is dialog.query_one(f"#{option_set}")
    for _ in range(steps):
        await pilot.press("down")
    await pilot.press("enter")


def shown_parameters(screen: MainScreen) -> dict:
    """The fitted parameters of the log shown."""
    return dict(screen.logs.result.params)


@needs_real_logs
@at_80x24
async def test_the_real_pd_run_opened_with_zero_down_is_the_command_lines_fit(pilot, app, watch):
    """`jointid fit --csv pendulum_pd.csv --zero down`: the same I and h, to the digits the readouts show."""
    path = REAL_LOGS / "pendulum_pd.csv"
    dialog = await open_dialog(pilot, app)
    dialog.query_one("#open-path", Input).value = str(path)
    await choose(pilot, dialog, "open-zero", list(ZEROS).index("down"))
    for _ in range(3):  # back to the path field: Enter there opens the file
        await pilot.press("shift+tab")
    await pilot.press("enter")
    await loaded(app, watch)
    screen = main_screen(app)
    expected = jointid.fit_log(path, zero="down")
    assert screen.logs.result.model.name == expected.result.model.name == LOG_MODEL
    shown = shown_parameters(screen)
    for name in ("I", "h"):
        assert shown[name] == pytest.approx(expected.params[name], rel=1e-9, abs=0)
        assert format_number(shown[name]) == format_number(expected.params[name])
    assert screen.logs.training.conventions["zero"] == "down"
    assert shown["I"] > 0.1 and shown["h"] > 0.1  # read as the joint it is, not as the plain model's I 0.028687


@pytest.fixture
def torque_and_current_logs(tmp_path, capsys):
    """A simulated torque log and the same log as a motor current: tau / (gear x kt x efficiency)."""
    torque = tmp_path / "arm_torque.csv"
    assert main(["simulate", "--out", str(torque), "--noise", "0.05", "--samples", "400",
                 "--true-coulomb", "0.2"]) == 0
    capsys.readouterr()
    lines = [line for line in torque.read_text().splitlines() if not line.startswith("#")]
    header, rows = lines[0].split(","), np.loadtxt(lines[1:], delimiter=",", ndmin=2)
    gear, kt, efficiency = 12.0, 0.025, 0.8
    rows[:, header.index("tau")] /= gear * kt * efficiency
    current = tmp_path / "arm_amps.csv"
    np.savetxt(current, rows, delimiter=",", header=",".join(header), comments="", fmt="%.17g")
    return torque, current, (gear, kt, efficiency)


@at_80x24
async def test_a_current_log_is_read_with_the_gear_kt_and_efficiency_typed(pilot, app, watch, torque_and_current_logs):
    torque, current, (gear, kt, efficiency) = torque_and_current_logs
    dialog = await open_dialog(pilot, app)
    dialog.query_one("#open-path", Input).value = str(current)
    assert dialog.query_one("#open-kt", Input).disabled  # only once Current is chosen
    await choose(pilot, dialog, "open-effort", 2)
    kt_field = dialog.query_one("#open-kt", Input)
    assert not kt_field.disabled
    for field, value in (("open-gear", gear), ("open-kt", kt), ("open-efficiency", efficiency)):
        dialog.query_one(f"#{field}", Input).value = f"{value:g}"
    kt_field.focus()
    await pilot.press("enter")  # Enter in any field opens the path
    await loaded(app, watch)
    shown = shown_parameters(main_screen(app))
    library = jointid.fit_log(current, effort="current", gear=gear, kt=kt, efficiency=efficiency)
    as_torque = jointid.fit_log(torque)  # the same joint, its torque logged directly
    for name, value in library.params.items():
        assert shown[name] == pytest.approx(value, rel=1e-9, abs=1e-12)
        assert shown[name] == pytest.approx(as_torque.params[name], rel=1e-6, abs=1e-9)
    assert main_screen(app).last_reading.effort.current_factor == pytest.approx(gear * kt * efficiency)


@pytest.mark.parametrize("field, typed, said", [
    ("open-kt", "", "A current log needs kt"),
    ("open-kt", "abc", "kt must be a finite number; got 'abc'"),
    ("open-gear", "-2", "Gear must be a finite number greater than 0; got '-2'"),
    ("open-efficiency", "1.5", "Efficiency must be a number greater than 0 and at most 1; got '1.5'"),
    ("open-kt", "nan", "kt must be a finite number; got 'nan'"),
])
@at_80x24
async def test_a_value_typed_wrongly_is_a_notification_and_the_dialog_stays(pilot, app, watch, tmp_path, field,
                                                                            typed, said):
    path = tmp_path / "log.csv"
    path.write_text("t,q,tau\n0,0,0\n")
    dialog = await open_dialog(pilot, app)
    dialog.query_one("#open-path", Input).value = str(path)
    await choose(pilot, dialog, "open-effort", 2)
    dialog.query_one("#open-kt", Input).value = "0.02"
    dialog.query_one(f"#{field}", Input).value = typed
    dialog.query_one(f"#{field}", Input).focus()
    send_burst(app, "enter", "enter")  # key repeat: one refusal, no load, no crash
    await watch.until(app, lambda: any(said in n.message for n in app._notifications), "the refusal")
    await pilot.pause()
    assert app.screen is dialog and main_screen(app).logs is None
    assert not any(isinstance(s, LoadingScreen) for s in app.screen_stack)
    assert len(app._notifications) == 1  # one box per kind (JointIdApp.on_notify)


@at_80x24
async def test_enter_enter_in_a_current_field_loads_the_log_once(pilot, app, watch, torque_and_current_logs):
    _, current, (gear, kt, efficiency) = torque_and_current_logs
    dialog = await open_dialog(pilot, app)
    dialog.query_one("#open-path", Input).value = str(current)
    await choose(pilot, dialog, "open-effort", 2)
    dialog.query_one("#open-kt", Input).value = f"{kt:g}"
    dialog.query_one("#open-kt", Input).focus()
    send_burst(app, "enter", "enter")
    await closed(app, watch, dialog)
    await loaded(app, watch)
    await watch.until(app, lambda: any(n.title == "Log loaded" for n in app._notifications), "the notification")
    assert len(app.screen_stack) == 1 and main_screen(app).logs is not None
    assert [n.title for n in app._notifications] == ["Log loaded"]


@at_80x24
async def test_the_dialog_fits_80x24_with_every_option(pilot, app, watch):
    dialog = await open_dialog(pilot, app)
    box = dialog.query_one("Vertical").content_region
    for widget in dialog.query("RadioButton, Checkbox, #open-current > *, #open-path, .dialog--hint"):
        region = widget.region
        assert region.height >= 1 and box.contains_region(region), (widget, region, box)
    assert dialog.query_one("#open-tree").region.height >= 4  # room to pick a file


def toast_lines(app) -> list[str]:
    """The text of the notification on screen, line by line as drawn."""
    from textual.geometry import Region
    from textual.widgets._toast import Toast

    toast = app.screen.query_one(Toast)
    width, height = toast.size
    lines = [strip.text.strip("▌ ") for strip in toast.render_lines(Region(0, 0, width, height))]  # its left edge
    return [line for line in lines if line]


@at_80x24
async def test_a_long_path_in_a_notification_wraps_between_its_folders(pilot, app, watch, tmp_path, capsys):
    folder = tmp_path / "a_folder_with_a_rather_long_name" / "and_another_one_below_it"
    folder.mkdir(parents=True)
    path = folder / "a_log_with_a_long_name.csv"
    assert main(["simulate", "--out", str(path), "--noise", "0.05", "--samples", "400"]) == 0
    capsys.readouterr()
    dialog = await open_dialog(pilot, app)
    dialog.query_one("#open-path", Input).value = str(path)
    await pilot.press("enter")
    await loaded(app, watch)
    from textual.widgets._toast import Toast

    await watch.until(app, lambda: len(app.screen.query(Toast)) == 1 and app.screen.query_one(Toast).size.height > 2,
                      "the notification laid out")
    assert all("\n" not in n.message for n in app._notifications)  # its text stays one line; the box wraps it
    lines = toast_lines(app)
    text = str(path)
    start = next((i for i, line in enumerate(lines) if line.startswith(text[:10])), None)
    assert start is not None, lines
    joined, index = "", start
    while len(joined) < len(text):  # the path's lines, each ending at a separator but the last
        joined += lines[index]
        if len(joined) < len(text):
            assert lines[index].endswith("/"), lines
        index += 1
    assert joined.startswith(text), lines


def test_fold_paths_breaks_only_long_paths_and_only_after_separators():
    from tui.notices import fold_paths

    assert fold_paths("Wrote /a/b.json and /a/b.svg", 20) == "Wrote /a/b.json and /a/b.svg"
    folded = fold_paths("Log /home/student/logs/pendulum_pd.csv: 1170 rows", 16)
    assert folded == "Log /home/student/\nlogs/\npendulum_pd.csv: 1170 rows"
    assert fold_paths("no_separator_but_long_enough", 5) == "no_separator_but_long_enough"


@pytest.fixture
def train_and_test(tmp_path, capsys):
    """A training and a held-out log, and the first line `jointid fit --csv` prints for the training log (run
    before the app starts: Textual captures what is printed while it runs)."""
    train, test = tmp_path / "train.csv", tmp_path / "test.csv"
    assert main(["simulate", "--out", str(train), "--noise", "0.05", "--samples", "600"]) == 0
    assert main(["simulate", "--motion", "test", "--out", str(test), "--noise", "0.05", "--samples", "200"]) == 0
    capsys.readouterr()
    assert main(["fit", "--csv", str(train)]) == 0
    return train, test, capsys.readouterr().out.splitlines()[0]


@at_80x24
async def test_one_count_of_samples_fitted_in_the_note_the_notification_and_the_command_line(
        pilot, app, watch, train_and_test):
    train, test, first_line = train_and_test
    dialog = await open_dialog(pilot, app)
    dialog.query_one("#open-path", Input).value = str(train)
    await pilot.press("enter")
    await loaded(app, watch)
    await watch.until(app, lambda: any(n.title == "Log loaded" for n in app._notifications), "the notification")
    screen = main_screen(app)
    fitted = screen.result.training.count
    decimated = len(range(0, 600, screen.logs.filter.decimation))
    assert fitted == decimated - int((~screen.logs.exclusions.kept).sum())  # counted apart from the text
    words = f"{fitted} fitted"
    note = str(screen.query_one("#log-note").render())
    message = " ".join(next(n for n in app._notifications if n.title == "Log loaded").message.split())
    assert f"; {words}" in note and f", {words} after" in message and f", {words} after" in first_line
    assert "samples fitted" not in message + first_line  # no second count called fitted
    # A held-out log is predicted, not fitted: its line counts its samples without the word.
    dialog = await open_dialog(pilot, app)
    dialog.query_one("#open-path", Input).value = str(test)
    await choose(pilot, dialog, "open-role", 1)
    await pilot.press("shift+tab")
    await pilot.press("enter")
    await loaded(app, watch)
    await watch.until(app, lambda: any(n.title == "Held-out log loaded" for n in app._notifications), "its note")
    held_out = next(n for n in app._notifications if n.title == "Held-out log loaded").message
    assert "fitted" not in held_out and "200 samples" in " ".join(held_out.split())


@at_80x24
async def test_r_on_a_log_refits_it_with_the_log_defaults_and_keeps_the_log(pilot, app, watch, tmp_path, capsys):
    path = tmp_path / "train.csv"
    assert main(["simulate", "--out", str(path), "--noise", "0.05", "--samples", "400", "--true-coulomb", "0.2"]) == 0
    capsys.readouterr()
    dialog = await open_dialog(pilot, app)
    dialog.query_one("#open-path", Input).value = str(path)
    await pilot.press("enter")
    await loaded(app, watch)
    screen = main_screen(app)
    assert screen.settings.model == LOG_MODEL
    screen.change_fit("model", "plain")
    screen.change_fit("constrained", True)
    await watch.until(app, lambda: screen.logs.result.model.name == "plain" and screen.logs.result.constrained,
                      "the plain, constrained refit")
    await pilot.press("r")
    await watch.until(app, lambda: screen.logs.result.model.name == LOG_MODEL and not screen.logs.result.constrained,
                      "the refit with the log defaults")
    assert screen.logs is not None and screen.logs.training.path == str(path)  # r never leaves the log
    expected = jointid.fit_log(path)
    for name, value in expected.params.items():
        assert shown_parameters(screen)[name] == pytest.approx(value, rel=1e-9, abs=1e-12)
    reset = [n.message for n in app._notifications if n.title == "Reset"]
    assert reset and f"model {LOG_MODEL}" in reset[-1] and "an unconstrained fit" in reset[-1]
    app.clear_notifications()
    await pilot.press("r")  # nothing left to undo: said so, nothing refitted
    assert "already" in [n.message for n in app._notifications if n.title == "Reset"][-1]
    assert "r Reset" not in str(screen.query_one("KeyFooter").render())  # off the footer on a log (80 columns)


@at_80x24
async def test_after_reset_the_footers_digits_choose_a_motion_not_a_seed(pilot, app, watch):
    screen = main_screen(app)
    seed = screen.query_one("#seed", Stepper)
    seed.focus()
    await pilot.press("r")
    assert isinstance(screen.focused, ChoiceList)
    await pilot.press("2")
    assert screen.settings.motion == "slow" and screen.settings.seed == 7


@at_80x24
async def test_a_log_opened_over_the_lesson_gives_its_model_back_when_left(pilot, app, watch, tmp_path, capsys):
    path = tmp_path / "train.csv"
    assert main(["simulate", "--out", str(path), "--noise", "0.05", "--samples", "400"]) == 0
    capsys.readouterr()
    screen = main_screen(app)
    dialog = await open_dialog(pilot, app)
    dialog.query_one("#open-path", Input).value = str(path)
    await pilot.press("enter")
    await loaded(app, watch)
    assert screen.settings.model == LOG_MODEL and "model coulomb+bias" in str(screen.query_one("#title").render())
    await pilot.press("c")
    assert screen.logs is None and screen.settings.model == "plain"


@at_80x24
async def test_a_model_chosen_for_the_log_shown_carries_over_to_the_next(pilot, app, watch, tmp_path, capsys):
    first, second = tmp_path / "first.csv", tmp_path / "second.csv"
    for path, seed in ((first, "1"), (second, "2")):
        assert main(["simulate", "--out", str(path), "--noise", "0.05", "--samples", "400", "--seed", seed]) == 0
    capsys.readouterr()
    screen = main_screen(app)
    for path in (first, second):
        dialog = await open_dialog(pilot, app)
        dialog.query_one("#open-path", Input).value = str(path)
        await pilot.press("enter")
        await loaded(app, watch)
        if path == first:
            screen.change_fit("model", "coulomb")  # as p would, the command line's --model coulomb
            await watch.until(app, lambda: screen.logs.result.model.name == "coulomb", "the refit")
    assert screen.logs.training.path == str(second) and screen.logs.result.model.name == "coulomb"


def test_the_log_defaults_are_one_function_for_every_face():
    from jointid.cli.log_arguments import log_model

    assert default_log_model("torque") == default_log_model("current") == default_log_model(None) == LOG_MODEL
    assert default_log_model("voltage") == VOLTAGE_LOG_MODEL

    class Args:
        effort = "voltage"

    assert log_model(Args()) == VOLTAGE_LOG_MODEL
