"""Snapshot tests of the explorer on joint logs, pinned under snapshots/test_log_snapshots/.

The logs are written by `jointid simulate` into a temporary folder that is made
the current directory, so the paths on screen are the same on every run.
Regenerate on purpose with `--snapshot-update` and look at the PNGs first.

A fit's readouts are compared at their printed precision (support/printed_numbers.py: one unit of the last digit
of a 6-decimal readout), every tag and every word exactly: the last digit of a real log's Fc or RMSE differs
between CPUs (OPENBLAS_CORETYPE=Prescott shows it on any machine), the layout does not.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import pytest_textual_snapshot
from support.log_files import CORPUS
from support.printed_numbers import CHART_CELLS, screens_agree
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


@pytest.fixture(autouse=True)
def readouts_at_their_precision(monkeypatch):
    """The snapshots of this module match when their layout and words are the same and their numbers agree at
    their printed precision (the plugin compares through its extension's `matches`)."""
    def matches(self, *, serialized_data, snapshot_data) -> bool:
        return snapshot_data is not None and screens_agree(str(snapshot_data), str(serialized_data))

    monkeypatch.setattr(pytest_textual_snapshot.SVGImageExtension, "matches", matches)


def test_a_readout_one_unit_off_or_a_chart_pixel_moved_matches_and_a_word_a_place_or_a_colour_does_not():
    # A stored picture of the real log changed as another CPU changed it (0.174814 -> 0.174815, a dot of the chart
    # moved to the next cell), and as it must not.
    stored = (Path(__file__).resolve().parents[2] / "snapshots" / "test_log_snapshots"
              / "test_a_real_log_with_pushes_shows_what_was_left_out[80x24].svg").read_text(encoding="utf-8")
    readout = "Fc&#160;0.174814"
    assert readout in stored
    assert screens_agree(stored, stored.replace(readout, "Fc&#160;0.174815"))
    assert not screens_agree(stored, stored.replace(readout, "Fc&#160;0.174816"))
    assert not screens_agree(stored, stored.replace(readout, "Fv&#160;0.174814"))
    run = re.search(r'<text class="[\w-]+" x="([\d.]+)"[^>]*>[^<]*' + readout, stored)
    moved = stored[:run.start(1)] + f"{float(run.group(1)) + 12.2:.1f}" + stored[run.end(1):]
    assert not screens_agree(stored, moved)  # the readout one column to the right
    dots = [m for m in re.finditer(r'>([\u2800-\u28ff])<', stored)]
    assert len(dots) > 2 * CHART_CELLS
    def with_dots(count):
        text = stored
        for m in reversed(dots[:count]):
            text = text[:m.start(1)] + chr(ord(m.group(1)) ^ 1) + text[m.end(1):]  # one dot on or off
        return text
    assert screens_agree(stored, with_dots(2)) and not screens_agree(stored, with_dots(CHART_CELLS + 1))
    styles = re.findall(r"\.terminal-r\d+ \{ fill: (#[0-9a-f]{6})", stored)
    assert not screens_agree(stored, stored.replace(styles[0], "#123456", 1))  # a colour


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
