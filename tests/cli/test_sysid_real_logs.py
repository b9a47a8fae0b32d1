"""The two real SysId logs of ../shared/real-logs/wpilog/ through the command line, checked against WPILib SysId's
own analysis re-implemented here with numpy (read with robotpy-wpiutil's DataLogReader, not jointid's reader).

The reference follows allwpilib tools/sysid: DataSelector splits the tests by the state entry, AnalysisManager
takes the FIRST run of each (runs[0]), samples at the voltage entry's time stamps with position and velocity
interpolated; quasistatic samples slower than the velocity threshold (0.2 units/s) are dropped; acceleration is
the 3-point central difference of the LOGGED velocity; each dynamic test is trimmed to start at its largest
acceleration and to end at 90 % of its top speed; then FeedforwardAnalysis' ordinary least squares of
acceleration on velocity, voltage and sgn(velocity): kV = -alpha/beta, kA = 1/beta, kS = -gamma/beta.
"""

import contextlib
import io
import json
import shlex
from pathlib import Path

import numpy as np
import pytest
from support.cli_support import run
from support.real_logs import REAL_LOGS, needs_real_logs

wpiutil = pytest.importorskip("wpiutil")

REAL = REAL_LOGS / "wpilog"
SWERVE = REAL / "swerve_drive_sysid.wpilog"
PIVOT = REAL / "pivot_sysid_no_voltage.wpilog"
MOTORS = ("drive-backleft", "drive-backright", "drive-frontleft", "drive-frontright")
ROUTINE = "SwerveSubsystem"
VELOCITY_THRESHOLD = 0.2
"""SysId's default quasistatic velocity threshold (AnalysisManager::Settings::velocityThreshold)."""

pytestmark = needs_real_logs


def _entries(path: Path) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Name -> (times s, values) of the routine's entries, read record by record with DataLogReader."""
    from wpiutil.log import DataLogReader

    names, data = {}, {}
    for record in DataLogReader(str(path)):
        if record.isStart():
            start = record.getStartData()
            if start.name.endswith(ROUTINE):
                names[start.entry] = (start.name, start.type)
        elif not record.isControl() and record.getEntry() in names:
            name, kind = names[record.getEntry()]
            value = record.getString() if kind == "string" else record.getDouble()
            data.setdefault(name, []).append((record.getTimestamp() * 1e-6, value))
    return {name: (np.array([t for t, _ in rows]), np.array([v for _, v in rows], dtype=object if
                                                             isinstance(rows[0][1], str) else float))
            for name, rows in data.items()}


def _first_runs(state_times, states) -> dict[str, tuple[float, float]]:
    """Test -> (start, end) s of its first run: from its first state record to the next change (DataSelector)."""
    runs = {}
    for k in range(len(states)):
        if k and states[k] == states[k - 1]:
            continue
        change = next((j for j in range(k + 1, len(states)) if states[j] != states[k]), len(states) - 1)
        if states[k] != "none" and states[k] not in runs:
            runs[states[k]] = (state_times[k], state_times[change])
    return runs


def sysid_reference(path: Path, motor: str) -> dict[str, float]:
    """kS, kV, kA of one motor as SysId's FeedforwardAnalysis computes them (see the module's docstring)."""
    entries = _entries(path)
    state_times, states = entries[f"sysid-test-state-{ROUTINE}"]
    vt, volts = entries[f"voltage-{motor}-{ROUTINE}"]
    pt, positions = entries[f"position-{motor}-{ROUTINE}"]
    wt, velocities = entries[f"velocity-{motor}-{ROUTINE}"]
    rows = []
    for test, (start, end) in _first_runs(state_times, states).items():
        inside = (vt >= start) & (vt < end)
        t, voltage = vt[inside], volts[inside]
        velocity = np.interp(t, wt, velocities)
        acceleration = np.full(len(t), np.nan)
        acceleration[1:-1] = (velocity[2:] - velocity[:-2]) / (t[2:] - t[:-2])
        keep = np.isfinite(acceleration)
        if test.startswith("quasistatic"):
            keep &= np.abs(velocity) >= VELOCITY_THRESHOLD
        else:
            along = np.sign(velocity) * acceleration  # acceleration in the direction of motion
            along[~np.isfinite(along)] = -np.inf
            strongest = int(np.argmax(along))
            top = np.max(np.abs(velocity))
            reached = strongest + int(np.argmax(np.abs(velocity[strongest:]) > 0.9 * top))
            window = np.zeros(len(t), dtype=bool)
            window[strongest: reached + 1] = True
            keep &= window
        rows.append(np.column_stack([velocity[keep], voltage[keep], np.sign(velocity[keep]),
                                     acceleration[keep]]))
    data = np.vstack(rows)
    (alpha, beta, gamma), *_ = np.linalg.lstsq(data[:, :3], data[:, 3], rcond=None)
    return {"kS": -gamma / beta, "kV": -alpha / beta, "kA": 1 / beta}


@pytest.fixture(scope="module")
def swerve_fit():
    """`jointid fit --wpilog swerve_drive_sysid.wpilog --json` with no other flag."""
    from jointid.cli import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        status = main(["fit", "--wpilog", str(SWERVE), "--json"])
    assert status == 0
    return json.loads(out.getvalue())


def test_the_reference_reproduces_sysids_own_front_left_gains():
    # The README quotes SysId's analysis of this log: kS about 0.19 V, kV about 2.46 V s/m, kA about 0.22 V s²/m.
    gains = sysid_reference(SWERVE, "drive-frontleft")
    assert gains["kV"] == pytest.approx(2.46, rel=0.02)
    assert gains["kS"] == pytest.approx(0.19, abs=0.05)
    assert gains["kA"] == pytest.approx(0.22, rel=0.35)


def test_the_swerve_log_fits_with_no_flags_all_four_motors_pooled_per_metre(swerve_fit):
    names = [run["name"] for run in swerve_fit["runs"]]
    assert len(names) == 4 * 5 and all(any(name.startswith(motor + " ") for motor in MOTORS) for name in names)
    reading = " ".join(swerve_fit["sysid_reading"])
    assert "drives 4 motors" in reading and "pooled as one mechanism" in reading
    assert "q in metres" in reading
    assert "kG" not in swerve_fit["pooled"]["estimate"]  # no cos of metres
    assert swerve_fit["mechanism"]["mechanism"] == "simple"  # a drive: SimpleMotorFeedforward, chosen unasked
    kv = swerve_fit["pooled"]["estimate"]["kV"]
    for motor in MOTORS:  # one mechanism: within 6 % of every motor's own SysId kV
        reference = sysid_reference(SWERVE, motor)["kV"]
        assert abs(kv - reference) / reference < 0.06, (motor, kv, reference)


def test_the_repeated_test_is_two_runs_never_merged_across_its_gap(swerve_fit):
    runs = {run["name"]: run for run in swerve_fit["runs"]}
    first = runs["drive-frontleft quasistatic-forward #1"]["logs"]["training"]
    second = runs["drive-frontleft quasistatic-forward #2"]["logs"]["training"]
    assert first["sysid_test"].endswith("#1") and second["sysid_test"].endswith("#2")
    reading = " ".join(swerve_fit["sysid_reading"])
    assert "quasistatic-forward was run 2 times, kept apart" in reading
    entries = _entries(SWERVE)
    state_times, states = entries[f"sysid-test-state-{ROUTINE}"]
    gap_start = state_times[np.flatnonzero(states == "none")[0]]  # the first run's end, 23.5 s before the second
    assert f"quasistatic-forward #1 (t = 251.89" in reading and gap_start == pytest.approx(254.268, abs=1e-3)


def test_the_logged_velocitys_lag_is_reported_for_each_motor(swerve_fit):
    lags = [run["logs"]["training"]["velocity_lag_s"] for run in swerve_fit["runs"]]
    assert all(0.08 < lag < 0.2 for lag in lags)  # a SPARK MAX's 32 ms deltas averaged eight deep
    assert "The logged velocities lag the positions' derivatives by" in " ".join(swerve_fit["sysid_reading"])


def test_each_suggested_command_line_pastes_as_is(capsys, swerve_fit):
    from jointid.cli import main

    reading = " ".join(swerve_fit["sysid_reading"])
    command = reading.split("`")[1]
    argv = shlex.split(command)
    assert argv[:3] == ["jointid", "fit", "--wpilog"] and "--sysid-motor" in argv
    assert main(argv[1:] + ["--json"]) == 0
    one = json.loads(capsys.readouterr().out)
    assert [run["name"] for run in one["runs"]][0] == "quasistatic-forward #1"


def test_the_pivot_log_without_voltage_is_one_line_naming_what_is_missing(capsys):
    status, out, err = run(capsys, "fit", "--wpilog", PIVOT)
    assert status == 2 and out == "" and err.count("\n") == 1
    assert "no voltage entry for routine 'Pivot'" in err
