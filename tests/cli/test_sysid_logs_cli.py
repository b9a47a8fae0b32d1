"""`jointid fit --wpilog` on SysId logs as teams record them: what the text says, and bad input in one line.

The logs are a simple motor in closed form (tests/support/sysid_motor_logs.py), written with robotpy-wpiutil.
"""

import json
import shlex

import pytest
from support.cli_support import run
from support.sysid_motor_logs import GAINS, MotorRoutine, write_motor_log

wpiutil = pytest.importorskip("wpiutil")


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    """A drive in metres with a test too short to fit, a velocity-only roller, two motors, a state entry alone."""
    folder = tmp_path_factory.mktemp("sysid-cli")
    state_only = folder / "state-only.wpilog"
    from wpiutil.log import DoubleLogEntry, StringLogEntry

    writer = wpiutil.DataLogWriter(str(state_only))
    state = StringLogEntry(writer, "sysid-test-state-shooter", 1)
    battery = DoubleLogEntry(writer, "/SystemStats/BatteryVoltage", 1)
    for k in range(40):
        state.append("quasistatic-forward", 1000 + 20_000 * k)
        battery.append(12.3, 1000 + 20_000 * k)
    writer.flush()
    writer.stop()
    return {
        "short": write_motor_log(folder / "short.wpilog", MotorRoutine(short={"dynamic-reverse": 12})),
        "roller": write_motor_log(folder / "roller.wpilog", MotorRoutine(routine="roller", position_unit=None,
                                                                         velocity_unit="Rotation per Second")),
        "two": write_motor_log(folder / "two.wpilog", MotorRoutine(motors={"left": GAINS, "Moteur Droite": GAINS})),
        "state-only": state_only,
    }


def test_a_test_too_short_is_named_in_the_text_with_its_reason(capsys, logs):
    status, out, err = run(capsys, "fit", "--wpilog", logs["short"])
    assert (status, err) == (0, "")
    assert "Left out: dynamic-reverse, too short to fit: 12 samples" in out
    status, out, err = run(capsys, "fit", "--wpilog", logs["short"], "--json")
    document = json.loads(out)
    assert any(note.startswith("Left out: dynamic-reverse") for note in document["sysid_reading"])
    assert document["runs"][0]["logs"]["training"]["sysid_left_out"][0]["run"] == "dynamic-reverse"


def test_a_velocity_only_log_is_fitted_and_says_so(capsys, logs):
    status, out, err = run(capsys, "fit", "--wpilog", logs["roller"], "--json")
    assert (status, err) == (0, "")
    document = json.loads(out)
    assert document["runs"][0]["logs"]["training"]["position_source"] == "integrated velocity"
    assert document["runs"][0]["logs"]["training"]["velocity_lag_s"] is None
    assert "kG" not in document["pooled"]["estimate"]  # an integrated velocity is no absolute angle
    assert any("q is the logged velocity 'velocity-left-roller' integrated" in note
               for note in document["sysid_reading"])


def test_the_suggested_command_for_one_motor_pastes_as_is(capsys, logs):
    status, out, err = run(capsys, "fit", "--wpilog", logs["two"])
    assert status == 0
    line = next(line for line in out.splitlines() if "pooled as one mechanism" in line)
    argv = shlex.split(line.split("`")[1])
    assert argv[-2:] == ["--sysid-motor", "Moteur Droite"]
    status, out, err = run(capsys, *argv[1:], "--json")
    assert (status, err) == (0, "")
    assert json.loads(out)["runs"][0]["logs"]["training"]["sysid_motor"] == "Moteur Droite"


@pytest.mark.parametrize(("case", "extra", "expected"), [
    ("two", ("--entry", "q=sysid-test-state-drive,tau=voltage-left-drive"),
     "entry 'sysid-test-state-drive' holds string, not numbers"),
    ("state-only", (), "no voltage entry for routine 'shooter', nor any position- or velocity-<motor>-shooter"),
    ("two", ("--units", "rotations"), "is in 'Meter', a length, not an angle; leave --units out"),
    ("two", ("--model", "coulomb+angle-offset"), "its gravity term takes cos(q), and q here is a length in metres"),
    ("two", ("--sysid-motor", "right"), "--sysid-motor 'right': the log has no SysId motor or routine"),
    ("two", ("--exclude", "1:2"), "--exclude 1:2 holds no sample of any test; the tests span 20 to"),
    ("two", ("--train-window", "1:2"), "no samples in the training window 1:2 s; the samples span 20 to"),
    ("roller", ("--units", "meters"), "--units meters: entry 'velocity-left-roller' is in 'Rotation per Second', an"),
])
def test_bad_input_is_one_line_and_status_two(capsys, logs, case, extra, expected):
    status, out, err = run(capsys, "fit", "--wpilog", logs[case], *extra)
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and expected in err, err


def test_sysid_flags_need_a_data_log(capsys):
    status, out, err = run(capsys, "fit", "--sysid-motor", "left")
    assert status == 2 and "--sysid-motor: only for" in err
