"""Snapshot tests of the explorer on joint logs, pinned under snapshots/test_log_snapshots/.

The logs are written by `jointid simulate` into a temporary folder that is made
the current directory, so the paths on screen are the same on every run.
Regenerate on purpose with `--snapshot-update` and look at the PNGs first.
"""

from __future__ import annotations

import pytest
from support.log_files import CORPUS
from support.real_logs import REAL_LOGS, needs_real_logs
from support.robot_logs import robot_log, write_log
from support.tui_support import make_app
from test_snapshots import COMPACT, WIDE, steady

from jointid.cli import main
from jointid.logs.csv_reader import load_log
from jointid.logs.conventions import AngleConvention
from jointid.logs.request import load_joint_log
from jointid.model.terms import model_named
from jointid.options import LOG_MODEL
from jointid.studies.log_fit import LoadRequest, fit_log, fit_logs
from jointid.studies.runs import fit_runs


@pytest.fixture
def in_log_folder(tmp_path, monkeypatch):
    """A folder holding train.csv (rich motion, noise 0.1, 2000 samples), test.csv and bad.csv, made current."""
    monkeypatch.chdir(tmp_path)
    assert main(["simulate", "--noise", "0.1", "--samples", "2000", "--out", "train.csv"]) == 0
    assert main(["simulate", "--motion", "test", "--noise", "0.05", "--seed", "3", "--samples", "200",
                 "--out", "test.csv"]) == 0
    (tmp_path / "bad.csv").write_text(CORPUS["nan.csv"])
    return tmp_path


def log_app(heldout: bool, monkeypatch):
    """The explorer opened as `jointid --csv train.csv [--heldout test.csv]` opens it: the command line loads and
    fits the logs (with its log defaults) and hands them to the app, which is caught before it runs."""
    opened = {}
    with monkeypatch.context() as patch:  # undone before the snapshot runs the app
        patch.setattr("tui.app.JointIdApp.run", lambda app: opened.update(app=app))
        assert main(["--csv", "train.csv", *(["--heldout", "test.csv"] if heldout else [])]) == 0
    app = opened["app"]
    return make_app(app.initial_settings, app.initial_logs)


@pytest.mark.parametrize("heldout, size", [(True, WIDE), (False, COMPACT), (True, COMPACT)],
                         ids=["heldout-120x40", "training-80x24", "heldout-80x24"])
def test_explorer_on_a_log(snap_compare, in_log_folder, monkeypatch, heldout, size):
    assert snap_compare(log_app(heldout, monkeypatch), terminal_size=size, run_before=steady)


def test_a_bad_file_is_a_notification_and_the_log_stays(snap_compare, in_log_folder, monkeypatch):
    async def load_bad(pilot):
        steady(pilot)
        pilot.app.screen.start_loading(LoadRequest("bad.csv"))
        await pilot.app.workers.wait_for_complete()
        await pilot.pause()

    assert snap_compare(log_app(True, monkeypatch), terminal_size=WIDE, run_before=load_bad)


@pytest.mark.parametrize("window, size", [(None, WIDE), (601, COMPACT)], ids=["default-120x40", "window601-80x24"])
def test_a_jittered_robot_log_with_its_notes_and_sensitivity_check(snap_compare, tmp_path, monkeypatch, window, size):
    """300 Hz, +-10 % jitter, 12-bit angles: the notes say how it was resampled, differentiated and filtered;
    a 601-sample (2 s) smoothing window, its -3 dB point (about 0.53 Hz) below the 1.3 Hz cutoff, gets "your
    derivative settings decide this estimate" (q is smoothed before it is differentiated and everything is
    low-passed at the cutoff, so a narrow window such as 31 samples no longer decides anything)."""
    monkeypatch.chdir(tmp_path)
    write_log(tmp_path / "robot.csv", robot_log(300, duration=8.0))
    app = make_app(logs=fit_logs(load_log("robot.csv", window=window)))
    assert snap_compare(app, terminal_size=size, run_before=steady)


@needs_real_logs
@pytest.mark.parametrize("size", [WIDE, COMPACT], ids=["120x40", "80x24"])
def test_a_real_log_with_pushes_shows_what_was_left_out(snap_compare, monkeypatch, size):
    """The real pendulum's energy-shaping run: the three pushes shaded, standstill and the pushes' samples faint,
    the fitted line over every sample, and every readout still on screen."""
    monkeypatch.chdir(REAL_LOGS)
    app = make_app(logs=fit_log("pendulum_energy_shaping.csv", zero="down"))
    assert snap_compare(app, terminal_size=size, run_before=steady)


@needs_real_logs
@pytest.mark.parametrize("view", ["main", "runs"])
def test_the_real_pendulums_three_runs_at_80x24(snap_compare, monkeypatch, view):
    """`jointid --zero down --csv pd --csv ddp --csv energy_shaping`: the first run with the pooled fit named
    beside it, and u's view of every run beside the pooled fit (the table scrolls sideways at 80 columns)."""
    monkeypatch.chdir(REAL_LOGS)
    logs = [load_joint_log(LoadRequest(f"pendulum_{run}.csv", angle=AngleConvention("down")))
            for run in ("pd", "ddp", "energy_shaping")]
    app = make_app(logs=fit_runs(logs, model_named(LOG_MODEL)))

    async def open_view(pilot):
        steady(pilot)
        if view == "runs":
            await pilot.press("u")
            await pilot.pause()

    assert snap_compare(app, terminal_size=COMPACT, run_before=open_view)


@needs_real_logs
def test_a_real_logs_notes_at_80x24(snap_compare, monkeypatch):
    """n on the energy-shaping run: the notes in their own view, what was read and how, what was left out."""
    monkeypatch.chdir(REAL_LOGS)
    app = make_app(logs=fit_log("pendulum_energy_shaping.csv", zero="down"))

    async def open_notes(pilot):
        steady(pilot)
        await pilot.press("n")
        await pilot.pause()

    assert snap_compare(app, terminal_size=COMPACT, run_before=open_notes)
