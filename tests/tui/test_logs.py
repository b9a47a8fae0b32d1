"""Joint logs in the explorer: loading (and cancelling) in a worker, held-out logs, bad files, export."""

from __future__ import annotations

import dataclasses
import functools
import json
import math

import numpy as np
import pytest
from support.log_files import CORPUS, HEADER, good_rows
from support.tui_support import displayed_readouts, make_app, synchronous
from textual.widgets import Input

from jointid.cli import main
from jointid.estimation.low_pass import FilterRequest
from jointid.logs import csv_reader
from jointid.logs.csv_reader import load_log
from jointid.logs.table import LogError
from jointid.model.terms import model_named
from jointid.options import DEFAULT_ORDER, DEFAULT_WINDOW, LOG_MODEL
from jointid.present import charts
from jointid.present.charts import ordinal
from jointid.present.readouts import readouts
from jointid.studies import log_fit as logfit
from jointid.studies.log_fit import HELDOUT, LoadRequest
from tui.app import JointIdApp
from tui.screens.main import FROM_LOG, STATUS_LINES, MainScreen
from tui.widgets.direct_controls import ChoiceList
from tui.widgets.footer import KeyFooter
from tui.widgets.readouts import ReadoutPanel
from tui.widgets.stepper import Stepper

SIZE = (120, 40)


@pytest.fixture
def logs(tmp_path):
    """A noisy rich-motion training log and a test-motion held-out log, written by `jointid simulate`."""
    train, test = tmp_path / "train.csv", tmp_path / "test.csv"
    assert main(["simulate", "--noise", "0.1", "--samples", "600", "--out", str(train)]) == 0
    assert main(["simulate", "--motion", "test", "--noise", "0.05", "--seed", "3", "--samples", "200",
                 "--out", str(test)]) == 0
    return train, test


def tmp_path_of(path):
    """The folder a log was written in (the full status names it; the compact one must not)."""
    return path.parent


async def load(pilot, path, role="training", degrees=False, filtering=FilterRequest(), window=None):
    """Load a file as the Ctrl+O dialog would, and wait until the worker's outcome is shown."""
    pilot.app.screen.start_loading(LoadRequest(str(path), role, degrees, window=window, filtering=filtering))
    await pilot.app.workers.wait_for_complete()
    await pilot.pause()


def main_screen(app) -> MainScreen:
    """The explorer's main screen (under any dialog)."""
    return next(s for s in app.screen_stack if isinstance(s, MainScreen))


@synchronous
async def test_a_loaded_log_shows_the_cores_fit_of_the_same_file(logs, capsys):
    train, _ = logs
    capsys.readouterr()
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await load(pilot, train)
        screen = main_screen(app)
        # A log opened with Ctrl+O is fitted with the log defaults, as `jointid --csv` fits it.
        expected = logfit.fit_logs(load_log(train), model=model_named(LOG_MODEL)).result
        assert screen.query_one(ReadoutPanel).items == readouts(expected)
        # The default low-pass extends the log's ends instead of trimming them, and keeps every D-th sample,
        # D = rate / (20 cutoff) rounded down (about 20 per cutoff hertz); the fit leaves out what the robust
        # step found. The log has 600 samples over 8 s (`jointid simulate`'s grid).
        chosen, left = screen.logs.filter, screen.logs.exclusions
        assert chosen.rate == pytest.approx(599 / 8.0)
        step = math.floor(chosen.rate / (20 * chosen.cutoff))
        assert chosen.decimation == step
        assert screen.result.training.count == len(range(0, 600, step)) - int((~left.kept).sum())
        assert "No held-out data" in str(screen.query_one("#status").render())
        assert not screen.query_one("#heldout-chart").display  # no held-out log: its chart gives way


@synchronous
async def test_the_heldout_log_is_predicted_against_its_measured_torques(logs, capsys):
    train, test = logs
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await load(pilot, train, filtering=FilterRequest(0))  # all 600 samples, to see the chart thin them
        await load(pilot, test, HELDOUT)
        screen = main_screen(app)
        expected = logfit.fit_logs(load_log(train), load_log(test), model_named(LOG_MODEL),
                                   filtering=FilterRequest(0)).result
        assert screen.query_one(ReadoutPanel).items == readouts(expected)
        assert screen.result.heldout_rmse == pytest.approx(expected.heldout_rmse, rel=0, abs=0)
        assert "against measured torques" in str(screen.query_one("#status").render())
        assert "every 5th of 600 samples shown" in screen.query_one("#training-chart").data.summaries[0]


@synchronous
async def test_a_heldout_log_needs_a_training_log_first(logs):
    _, test = logs
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        before = displayed_readouts(app.screen)
        await load(pilot, test, HELDOUT)
        assert app.screen.logs is None and displayed_readouts(app.screen) == before
        assert [n.severity for n in app._notifications] == ["error"]


@synchronous
async def test_a_log_loaded_while_a_number_field_has_the_focus_refuses_nothing(logs):
    """The field shows 'from log' and gives up the focus: that text is the screen's, not typing to commit."""
    train, _ = logs
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        stepper = app.screen.query(Stepper).first()
        stepper.focus()
        await pilot.pause()
        await load(pilot, train)
        await pilot.pause()
        assert stepper.value == FROM_LOG and not stepper.has_focus
        assert [n.title for n in app._notifications if n.severity == "error"] == []


@synchronous
async def test_synthetic_controls_are_off_with_the_reason_and_come_back(logs):
    train, _ = logs
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        synthetic = displayed_readouts(app.screen)
        await load(pilot, train)
        screen = app.screen
        steppers = list(screen.query(Stepper))
        assert all(s.disabled and s.value == FROM_LOG for s in steppers)
        note = str(screen.query_one("#log-note").render())
        fitted = screen.result.training.count  # after the default low-pass's decimation (checked above)
        assert note == f"From log: c or 1/2/3 for synthetic\ntrain.csv: 600 rows, radians; {fitted} fitted"
        # The number fields and Reset give way: they do not apply to a log.
        assert not any(s.display for s in screen.query(".field")) and not screen.query_one("#reset-row").display
        choices = screen.query_one(ChoiceList)
        assert choices.pressed == "motion-log" and "motion-log" in choices.shown
        assert choices.render().plain.splitlines()[-1].endswith(" Log: train.csv ")
        await pilot.press("c")  # back to the synthetic experiment, as it was
        assert screen.logs is None and "motion-log" not in choices.shown
        assert displayed_readouts(screen) == synthetic
        assert [s.value for s in steppers] == ["0.00", "24", "7"] and not any(s.disabled for s in steppers)
        await load(pilot, train)
        await pilot.press("2")  # a motion key leaves the log too
        assert screen.logs is None and screen.settings.motion == "slow"


@synchronous
async def test_views_of_synthetic_settings_say_they_need_one(logs):
    train, _ = logs
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await load(pilot, train)
        await pilot.press("s")
        await pilot.press("m")
        assert isinstance(app.screen, MainScreen)
        # One box for the kind: the matrix's note replaced the sweep's.
        assert [n.message for n in app._notifications if "needs a synthetic" in n.message] == [
            "The cross-excitation matrix needs a synthetic experiment: press 1, 2, 3 or c to leave the log."]
        await pilot.press("e")  # the residuals of the log's fit
        assert str(app.screen.query_one("#residual-title").render()) == "Residuals: log train.csv"


@synchronous
async def test_escape_cancels_loading_and_keeps_the_current_state(tmp_path, monkeypatch):
    train = tmp_path / "long.csv"
    assert main(["simulate", "--samples", "20000", "--out", str(train)]) == 0
    # Tiny chunks make the load long enough to cancel part-way.
    monkeypatch.setattr(csv_reader, "read_table", functools.partial(csv_reader.read_table, chunk_bytes=64))
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        before = displayed_readouts(app.screen)
        app.screen.start_loading(LoadRequest(str(train)))
        await pilot.pause()
        assert type(app.screen).__name__ == "LoadingScreen"
        await pilot.press("escape")
        await app.workers.wait_for_complete()
        await pilot.pause()
        assert isinstance(app.screen, MainScreen) and app.screen.logs is None
        assert displayed_readouts(app.screen) == before
        assert [n.message for n in app._notifications] == ["Loading cancelled; nothing changed."]


BAD_FILES = sorted(CORPUS) + ["absent.csv", "a_directory"]

WINDOWS = {"shorter_than_window.csv": 7}
"""A Savitzky-Golay window given for a file, where its flaw is being shorter than the window: its 6 rows of a
still joint fill the 5-sample window chosen when q shows no motion, so the test asks for 7."""


def write_bad(folder, name):
    """One malformed file of the command line's corpus (or a missing file, or a folder)."""
    path = folder / name
    if name == "a_directory":
        path.mkdir()
    elif name in CORPUS:
        path.write_bytes(CORPUS[name].encode("latin-1"))
    return path


@pytest.mark.parametrize("role", ["training", HELDOUT])
@synchronous
async def test_bad_files_leave_everything_as_it_was(tmp_path, role):
    good = tmp_path / "good.csv"
    good.write_text("\n".join([HEADER, *good_rows(300)]) + "\n")
    bad_folder = tmp_path / "bad"
    bad_folder.mkdir()
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await load(pilot, good)
        screen = app.screen
        logs, before, settings = screen.logs, displayed_readouts(screen), screen.settings
        charts = [screen.query_one(f"#{c}-chart").data for c in ("training", "heldout")]
        for name in BAD_FILES:
            path = write_bad(bad_folder, name)
            window = WINDOWS.get(name)
            with pytest.raises(LogError) as expected:
                load_log(path, window=window)
            app.clear_notifications()
            await load(pilot, path, role, window=window)
            assert screen.logs is logs and displayed_readouts(screen) == before, name
            assert [screen.query_one(f"#{c}-chart").data for c in ("training", "heldout")] == charts
            assert [(n.message, n.severity) for n in app._notifications] == [(str(expected.value), "error")], name
        assert screen.settings == settings


@synchronous
async def test_a_bad_file_over_synthetic_data_keeps_the_settings(tmp_path):
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await pilot.press("2")
        before = displayed_readouts(app.screen)
        await load(pilot, write_bad(tmp_path, "nan.csv"))
        assert app.screen.logs is None and app.screen.settings.motion == "slow"
        assert displayed_readouts(app.screen) == before


async def export(pilot, folder):
    """Ctrl+S, type the folder, Enter."""
    await pilot.press("ctrl+s")
    field = pilot.app.screen.query_one("#export-folder", Input)
    field.value = str(folder)
    await pilot.press("enter")
    await pilot.pause()


def cli_json(capsys, *argv):
    """What `jointid fit ... --json` prints, parsed."""
    capsys.readouterr()
    assert main(["fit", *map(str, argv), "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@synchronous
async def test_export_writes_the_command_lines_json_and_an_svg_and_never_overwrites(logs, tmp_path, capsys):
    train, test = logs
    folder = tmp_path / "out"
    folder.mkdir()
    (folder / "train-fit.json").write_text("precious\n")
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await load(pilot, train)
        await load(pilot, test, HELDOUT)
        await export(pilot, folder)
        await export(pilot, folder)
        await export(pilot, tmp_path / "missing")
        model = main_screen(app).settings.model
    assert (folder / "train-fit.json").read_text() == "precious\n"
    # The explorer fits a log opened with Ctrl+O with the log defaults, as `jointid fit --csv` without --model.
    assert model == LOG_MODEL
    expected = cli_json(capsys, "--csv", train, "--heldout", test)
    for stem in ("train-fit-2", "train-fit-3"):
        assert json.loads((folder / f"{stem}.json").read_text()) == expected
        assert (folder / f"{stem}.svg").read_text().startswith("<svg")
    assert sorted(p.name for p in folder.iterdir()) == [
        "train-fit-2.json", "train-fit-2.svg", "train-fit-3.json", "train-fit-3.svg", "train-fit.json"]
    messages = [n.message for n in app._notifications]
    # The second export's note replaced the first's (one notification per kind).
    assert f"Wrote {folder / 'train-fit-3.json'} and {folder / 'train-fit-3.svg'}" in messages
    assert f"{tmp_path / 'missing'}: no such folder" in messages


@synchronous
async def test_export_of_a_synthetic_experiment_matches_fit_json(tmp_path, capsys):
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await pilot.press("2")
        await export(pilot, tmp_path)
    expected = cli_json(capsys, "--motion", "slow")
    assert json.loads((tmp_path / "jointid-slow-0.00-24-7.json").read_text()) == expected


@synchronous
async def test_the_open_dialog_is_usable_by_keyboard(logs, monkeypatch):
    train, _ = logs
    monkeypatch.chdir(train.parent)
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await pilot.press("ctrl+o")
        field = app.screen.query_one("#open-path", Input)
        assert field.has_focus and field.value == f"{train.parent}/"
        await pilot.press(*"train.csv", "enter")
        await app.workers.wait_for_complete()
        await pilot.pause()
        assert main_screen(app).logs.name == "train.csv"
        await pilot.press("ctrl+o", "escape")
        assert isinstance(app.screen, MainScreen)


def test_the_command_line_opens_the_explorer_on_a_log(logs, monkeypatch):
    train, test = logs
    opened = {}

    def fake_run(app):
        opened["logs"] = app.initial_logs

    monkeypatch.setattr("tui.app.JointIdApp.run", fake_run)
    assert main(["--csv", str(train), "--heldout", str(test)]) == 0
    assert opened["logs"].training.path == str(train) and opened["logs"].heldout.path == str(test)


@pytest.mark.parametrize("argv, words", [
    (["--csv", "absent.csv"], "absent.csv: cannot open"),
    (["--csv", "bad.csv"], "bad.csv, row 7, column 3 (qd): NaN is not a measurement"),
    (["--csv", "bad.csv", "--seed", "3"], "cannot apply to a log"),
    (["--heldout", "bad.csv"], "--heldout: only for fitting a log"),
])
def test_a_bad_log_on_the_command_line_is_one_line_before_the_app(tmp_path, monkeypatch, capsys, argv, words):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "bad.csv").write_text(CORPUS["nan.csv"])
    monkeypatch.setattr("tui.app.JointIdApp.run", lambda app: pytest.fail("the app started"))
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and len(captured.err.splitlines()) == 1 and words in captured.err


def test_ordinals():
    assert [ordinal(n) for n in (2, 3, 4, 11, 12, 13, 21, 112)] == ["2nd", "3rd", "4th", "11th", "12th", "13th", "21st", "112th"]


def test_log_charts_are_thinned_to_the_width():
    assert [charts.thin_stride(n, 80) for n in (10, 80, 81, 160, 161, 1_000_000)] == [1, 1, 2, 2, 3, 12500]


@synchronous
async def test_a_log_with_its_heldout_fits_80x24_without_scrolling(logs):
    train, test = logs
    app = make_app()
    async with app.run_test(size=(80, 24)) as pilot:
        await load(pilot, train)
        await load(pilot, test, HELDOUT)
        screen = app.screen
        side, panel = screen.query_one("#side"), screen.query_one(ReadoutPanel)
        assert screen.logs.heldout is not None
        assert side.max_scroll_y == 0 and panel.region.bottom <= side.region.bottom
        # What was read goes beside the readouts, file names only; the status keeps to its 4 rows.
        assert str(screen.query_one("#log-note").render()).splitlines() == [
            "From log: c or 1/2/3 for synthetic", f"train.csv: 600 rows, radians; {screen.result.training.count} fitted",
            "Held-out test.csv: 200 rows, radians"]
        status = screen.query_one("#status")
        assert status.size.height == STATUS_LINES and str(tmp_path_of(train)) not in str(status.render())
        footer = screen.query_one(KeyFooter).text
        assert "Close log" in footer and "Export" in footer and "…" not in footer


@synchronous
async def test_logs_opened_with_ctrl_o_are_differentiated_as_the_command_line_asked(tmp_path, monkeypatch):
    """`jointid --csv a.csv --window 51 --order 2`: a log opened later uses window 51, order 2 too."""
    angles_only = tmp_path / "encoder.csv"
    assert main(["simulate", "--encoder-counts", "4096", "--rate", "1000", "--duration", "2",
                 "--out", str(angles_only)]) == 0
    monkeypatch.chdir(tmp_path)
    app = JointIdApp(derivatives=(51, 2))
    async with app.run_test(size=SIZE) as pilot:
        await pilot.press("ctrl+o", *"encoder.csv", "enter")
        await app.workers.wait_for_complete()
        await pilot.pause()
        estimate = main_screen(app).logs.training.derivatives
        assert (estimate.window, estimate.order) == (51, 2)


def test_the_command_line_hands_window_and_order_to_the_explorer(logs, monkeypatch):
    train, _ = logs
    opened = {}
    monkeypatch.setattr("tui.app.JointIdApp.run", lambda app: opened.update(derivatives=app.derivatives))
    assert main(["--csv", str(train), "--window", "101", "--order", "3"]) == 0
    assert opened["derivatives"] == (101, 3)
    assert main(["--csv", str(train)]) == 0
    assert opened["derivatives"] == (DEFAULT_WINDOW, DEFAULT_ORDER)


@synchronous
async def test_closing_a_log_pushes_the_synthetic_fit_once(logs, monkeypatch):
    """One push-down per change: closing a log shows the synthetic fit once, a view pushes nothing."""
    train, _ = logs
    pushes = []
    show = MainScreen.show_source
    monkeypatch.setattr(MainScreen, "show_source", lambda screen: (pushes.append(screen.settings), show(screen)))
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await load(pilot, train)
        pushes.clear()
        await pilot.press("c")
        await pilot.pause()
        assert len(pushes) == 1
        await pilot.press("m")  # a view opened on the current settings pushes nothing
        await pilot.pause()
        assert len(pushes) == 1


@synchronous
async def test_a_jittered_log_shows_its_notes_and_the_sensitivity_warning(tmp_path):
    from support.robot_logs import robot_log, write_log

    path = write_log(tmp_path / "robot.csv", robot_log(300, duration=8.0))
    # q is smoothed before qd and qdd are taken from it, then everything is low-passed at about 1.3 Hz, so a narrow
    # window no longer decides anything; a 601-sample (2 s) one does: its -3 dB point is near 0.53 Hz, below the
    # cutoff, and it passes only 85 % of the motion's 2.7 rad/s (0.43 Hz) term. The automatic window, its -3 dB
    # point meant at 3 x the cutoff, should leave the estimate alone.
    for size, window in ((SIZE, None), ((80, 24), 601)):
        app = make_app()
        async with app.run_test(size=size) as pilot:
            await load(pilot, path, window=window)
            status = str(main_screen(app).query_one("#status").render())
            compact = size == (80, 24)  # names the moved parameters and leaves their errors to the readouts
            assert status.endswith("n: notes." if compact else "n: the notes (how the log was read, filtered and "
                                   "checked).")
            warned = ("The derivative settings move I" if compact
                      else "Your derivative settings decide this estimate") in status
            assert warned == (window is not None), status
            # The notes have their own view: n opens it, with everything the command line says of the log.
            await pilot.press("n")
            await pilot.pause()
            notes = str(app.screen.query_one("Static").render())
            assert type(app.screen).__name__ == "NotesScreen"
            assert "resampled" in notes and "Savitzky-Golay" in notes and "low-passed" in notes
            assert "Sensitivity check" in notes
            await pilot.press("escape")
            await pilot.pause()
            assert app.screen is main_screen(app)


@synchronous
async def test_k_and_the_model_refit_a_loaded_log_in_a_worker_and_a_stale_refit_is_dropped(logs, capsys):
    train, _ = logs
    capsys.readouterr()
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await load(pilot, train)
        screen = main_screen(app)
        loaded = screen.logs
        screen.change_fit("constrained", True)
        assert screen.logs is loaded  # the press returns at once: the refit runs in a worker
        await pilot.app.workers.wait_for_complete()
        await pilot.pause()
        expected = logfit.fit_logs(load_log(train), model=model_named(LOG_MODEL), constrained=True).result
        assert screen.logs.training is loaded.training and screen.logs.result.constrained
        assert screen.query_one(ReadoutPanel).items == readouts(expected)
        screen.change_fit("model", "coulomb")
        await pilot.app.workers.wait_for_complete()
        await pilot.pause()
        assert screen.logs.result.model.name == "coulomb" and screen.logs.result.constrained
        # A refit that lands after the user chose something else is not shown.
        shown = screen.logs
        stale = logfit.fit_logs(shown.training, constrained=False)
        screen.finish_refit(shown, dataclasses.replace(screen.settings, model="plain"), stale)
        assert screen.logs is shown


@synchronous
async def test_logs_opened_with_ctrl_o_are_read_in_the_command_lines_conventions(tmp_path, monkeypatch):
    """`jointid --csv a.csv --zero down --clockwise`: a log opened later is read with the same convention."""
    from jointid.logs.conventions import AngleConvention, LogConventions

    t = np.arange(400) * 0.01
    position = 0.3 * np.sin(2 * t)
    (tmp_path / "robot.csv").write_text("time,position,effort\n" + "".join(
        f"{a:.17g},{b:.17g},{c:.17g}\n" for a, b, c in zip(t, position, np.sin(position))))
    monkeypatch.chdir(tmp_path)
    app = JointIdApp(conventions=LogConventions(angle=AngleConvention("down", clockwise=True)))
    async with app.run_test(size=SIZE) as pilot:
        await pilot.press("ctrl+o", *"robot.csv", "enter")
        await app.workers.wait_for_complete()
        await pilot.pause()
        log = main_screen(app).logs.training
        half = (len(t) - log.data.count) // 2  # q = -pi/2 - position, trimmed at both ends alike
        np.testing.assert_allclose(log.data.q, -np.pi / 2 - position[half:len(t) - half], rtol=0, atol=1e-12)
        assert log.conventions["zero"] == "down" and log.conventions["clockwise"] is True


def test_the_command_line_hands_the_conventions_to_the_explorer(logs, monkeypatch):
    train, _ = logs
    opened = {}
    monkeypatch.setattr("tui.app.JointIdApp.run", lambda app: opened.update(conventions=app.conventions))
    assert main(["--csv", str(train), "--zero", "up", "--clockwise", "--columns", "t=t"]) == 0
    assert opened["conventions"].angle.zero == "up" and opened["conventions"].angle.clockwise
    assert opened["conventions"].columns.pairs == (("t", "t"),)


@synchronous
async def test_a_term_the_model_lacks_is_named_in_the_status_and_its_parameters_are_not_well_determined():
    from support.coulomb_joint import coulomb_joint_log

    from jointid import fit_log

    logs = fit_log(coulomb_joint_log(1), model="plain", sensitivity=False)
    app = make_app(logs=logs)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        status = str(app.screen.query_one("#status").render())
        assert "The residuals follow Coulomb friction (sign qd)" in status and "which the model lacks" in status
        panel = app.screen.query_one(ReadoutPanel)
        for name in logs.decided_by_omitted:
            assert name in status.split("which the model lacks")[1]
        assert panel.region.bottom <= app.screen.query_one("#side").region.bottom  # every readout on screen
