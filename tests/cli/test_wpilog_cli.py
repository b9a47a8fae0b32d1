"""Command line for WPILib data logs: log-info, fit --wpilog on a SysId routine, and bad logs refused in one line."""

import json
import socket

import pytest
from support.cli_support import run
from support.sysid_arm import (
    GAINS,
    TESTS,
    routine_samples,
    sysid_names,
    write_routine_log,
)

from jointid.cli import main

wpiutil = pytest.importorskip("wpiutil")


@pytest.fixture(scope="module")
def arm_log(tmp_path_factory):
    """A simulated SysId arm routine, positions in rotations (short tests: the acceptance is in tests/core)."""
    from support.sysid_arm import Routine

    folder = tmp_path_factory.mktemp("wpilog-cli")
    routine = Routine(quasistatic=2.5, dynamic=1.0)
    return write_routine_log(folder / "arm.wpilog", routine_samples(routine), routine)


def test_log_info_names_the_entries_and_the_routines_tests(capsys, arm_log):
    status, out, err = run(capsys, "log-info", arm_log)
    assert (status, err) == (0, "")
    assert "position-arm-motor-arm" in out and "Rotation per Second" in out
    assert "SysId routine 'arm', motor 'arm-motor'" in out
    assert all(test in out for test, _ in TESTS)
    status, out, err = run(capsys, "log-info", arm_log, "--json")
    document = json.loads(out)
    assert [run["test"] for run in document["sysid"][0]["runs"]] == [test for test, _ in TESTS]


def test_fit_wpilog_fits_the_four_tests_as_runs_in_volts(capsys, arm_log):
    status, out, err = run(capsys, "fit", "--wpilog", arm_log, "--json")
    assert (status, err) == (0, "")
    document = json.loads(out)
    assert document["model"] == "coulomb+angle-offset" and document["sysid_routine"] == "arm"
    assert [r["name"] for r in document["runs"]] == [test for test, _ in TESTS]
    pooled, errors = document["pooled"]["estimate"], document["pooled"]["std_error"]
    assert abs(pooled["kG"] - GAINS["kG"]) <= max(0.03 * GAINS["kG"], 3 * errors["kG"])
    assert abs(pooled["q0"] - GAINS["offset"]) < 0.01
    status, out, err = run(capsys, "fit", "--wpilog", arm_log)
    assert status == 0 and "4 SysId tests of routine 'arm'" in out and "dynamic-reverse" in out


def _write(path, build):
    writer = wpiutil.DataLogWriter(str(path))
    build(writer)
    writer.flush()
    writer.stop()
    return path


def _no_numbers(path):
    def build(writer):
        names = wpiutil.log.StringLogEntry(writer, "/Driver/Name", 1)
        names.append("kim", 10)
    return _write(path, build)


def _state_without_voltage(path):
    def build(writer):
        state = wpiutil.log.StringLogEntry(writer, "sysid-test-state-arm", 1)
        position = wpiutil.log.DoubleLogEntry(writer, "position-motor-arm", "Rotation", 1)
        for k in range(30):
            position.append(0.01 * k, 1000 + 5000 * k)
            state.append("quasistatic-forward", 1050 + 5000 * k)
    return _write(path, build)


def _truncated(path, source):
    data = source.read_bytes()
    path.write_bytes(data[: len(data) // 2 + 5])
    return path


@pytest.mark.parametrize(("case", "extra", "expected"), [
    ("truncated", (), "cut short or damaged"),
    ("no-numbers", (), "has no numeric entries"),
    ("state-without-voltage", (), "no voltage entry for routine 'arm'"),
    ("missing-entry", ("--entry", "q=/Arm/Position,tau=/Arm/Volts"), "--entry q=/Arm/Position: the log has no entry"),
    ("not-a-log", (), "is not a WPILib data log"),
])
def test_bad_logs_are_one_line_and_status_two(capsys, tmp_path, arm_log, case, extra, expected):
    path = tmp_path / f"{case}.wpilog"
    if case == "truncated":
        _truncated(path, arm_log)
    elif case == "no-numbers":
        _no_numbers(path)
    elif case == "state-without-voltage":
        _state_without_voltage(path)
    elif case == "missing-entry":
        path = arm_log
    else:
        path.write_text("time,q,tau\n0,0,0\n")
    for command in (("fit", "--wpilog", path, *extra), ("log-info", path)):
        if command[0] == "log-info" and case in ("missing-entry", "no-numbers", "state-without-voltage"):
            continue
        status, out, err = run(capsys, *command)
        assert status == 2 and out == ""
        assert err.count("\n") == 1 and expected in err, err


def test_entry_and_units_need_wpilog(capsys, tmp_path):
    status, out, err = run(capsys, "fit", "--units", "rotations")
    assert status == 2 and "--units: only for" in err


def test_a_sysid_log_with_renamed_entries_fits_through_an_entry_map(capsys, tmp_path):
    from support.sysid_arm import Routine

    routine = Routine(quasistatic=2.5, dynamic=1.0)
    names = {**sysid_names(routine), "position": "/Arm/Position", "velocity": "/Arm/Velocity"}
    path = write_routine_log(tmp_path / "renamed.wpilog", routine_samples(routine), routine, names=names)
    status, out, err = run(capsys, "fit", "--wpilog", path, "--json", "--entry",
                           f"q=/Arm/Position,tau={names['voltage']},state={names['state']}")
    assert (status, err) == (0, "")
    assert [r["name"] for r in json.loads(out)["runs"]] == [test for test, _ in TESTS]


def test_a_log_without_tests_is_one_log_for_fit_and_compare(capsys, tmp_path):
    from support.sysid_arm import ADVANTAGEKIT_NAMES, Routine

    routine = Routine(quasistatic=2.5, dynamic=1.0)
    samples = routine_samples(routine)[2:3]  # the dynamic-forward test alone: one stretch, no gaps
    path = write_routine_log(tmp_path / "one.wpilog", samples, routine, units="radians", names=ADVANTAGEKIT_NAMES,
                             metadata=False, extra_entries=False)
    entries = f"q={ADVANTAGEKIT_NAMES['position']},tau={ADVANTAGEKIT_NAMES['voltage']}"
    status, out, err = run(capsys, "fit", "--wpilog", path, "--entry", entries, "--units", "radians", "--json")
    assert (status, err) == (0, "")
    document = json.loads(out)
    assert document["model"] == "coulomb+bias" and document["logs"]["training"]["format"] == "wpilog"
    assert document["logs"]["training"]["entries"] == {"q": ADVANTAGEKIT_NAMES["position"],
                                                       "tau": ADVANTAGEKIT_NAMES["voltage"]}
    status, out, err = run(capsys, "compare", "--wpilog", path, "--entry", entries, "--units", "radians")
    assert (status, err) == (0, "") and "coulomb+angle-offset" in out


def test_the_explorer_opens_on_a_sysid_logs_tests_in_their_model(arm_log):
    opened = {}

    def explore(settings, loaded, derivatives, filtering, conventions):
        opened.update(settings=settings, loaded=loaded)
        return 0

    assert main(["--wpilog", str(arm_log)], explorer=explore) == 0
    assert opened["settings"].model == "coulomb+angle-offset"
    assert [run.name for run in opened["loaded"].runs] == [test for test, _ in TESTS]


def test_report_and_export_take_a_sysid_log_as_fit_does(capsys, arm_log, tmp_path):
    """A user's path from a SysId log: the report holds the pooled gains and the constructor line (it was a
    traceback), and the export writes the physical joint behind them through the motor, by the log or by the fit's
    JSON alike (it was refused as 'not one log', and the JSON as 'no I, h, B')."""
    import xml.etree.ElementTree as ET

    page = tmp_path / "arm.html"
    status, _, err = run(capsys, "report", "--wpilog", str(arm_log), "--gains", "wpilib", "--out", str(page))
    assert status == 0, err
    status, out, err = run(capsys, "fit", "--wpilog", str(arm_log), "--gains", "wpilib", "--motor", "NEO", "--gear",
                           "60", "--json")
    assert status == 0, err
    fitted = json.loads(out)
    html = page.read_text()
    assert fitted["gains"]["constructors"]["java"] in html and "Voltage (V)" in html
    drive = ("--motor", "NEO", "--gear", "60", "--mass", "4")
    status, _, err = run(capsys, "export", "--wpilog", str(arm_log), *drive, "--urdf", str(tmp_path / "a.urdf"))
    assert status == 0, err
    (tmp_path / "fit.json").write_text(out)
    status, _, err = run(capsys, "export", "--from-json", str(tmp_path / "fit.json"), "--mass", "4", "--urdf",
                         str(tmp_path / "b.urdf"))
    assert status == 0, err
    physical = fitted["motor"]["parameters"]
    for name in ("a.urdf", "b.urdf"):
        dynamics = ET.parse(tmp_path / name).find(".//dynamics")
        assert float(dynamics.get("damping")) == pytest.approx(physical["B"]["value"], rel=1e-9)
        assert float(dynamics.get("friction")) == pytest.approx(physical["Fc"]["value"], rel=1e-9)
    status, out, err = run(capsys, "export", "--wpilog", str(arm_log), "--mass", "4", "--urdf",
                           str(tmp_path / "c.urdf"))
    assert status == 2 and "gives gains in volts" in err and not (tmp_path / "c.urdf").exists()


@pytest.mark.parametrize("case", ["entry-name-not-utf8", "extra-header-not-utf8", "double-of-4-bytes",
                                  "unit-nested-200000-deep"])
def test_a_damaged_log_is_one_line_and_status_two_in_every_command(capsys, tmp_path, case):
    """Written byte by byte from the specification: each command that reads the log refuses it in one line (they
    were UnicodeDecodeError, TypeError and RecursionError tracebacks)."""
    from support.cli_support import refused
    from support.datalog_bytes import damaged_logs

    data, word = damaged_logs()[case]
    path = tmp_path / f"{case}.wpilog"
    path.write_bytes(data)
    entries = ("--entry", "q=q,tau=tau")
    commands = [("fit", "--wpilog", path, *entries),
                ("report", "--wpilog", path, *entries, "--out", tmp_path / "r.html"),
                ("export", "--wpilog", path, *entries, "--mass", "1", "--mujoco", tmp_path / "j.xml")]
    if case != "double-of-4-bytes":  # log-info counts records without decoding their numbers
        commands.append(("log-info", path))
    with socket.socket() as taken:  # serve reads the log before it listens: a taken port is never reached
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        commands.append(("serve", "--port", taken.getsockname()[1], "--wpilog", path, *entries))
        for command in commands:
            line = refused(capsys, *command)
            assert f"{path}: is damaged: " in line and word in line, (command[0], line)
    assert not (tmp_path / "r.html").exists() and not (tmp_path / "j.xml").exists()


def test_log_info_escapes_the_logs_names_and_units_as_every_message_does(capsys, tmp_path):
    """Entry names and units are the log's: a raw ESC, BEL or CR would drive the terminal (they were printed raw)."""
    from support.datalog_bytes import joint_log

    from jointid.text_safety import shown_name

    name, unit = "q\x1b[2J\x07", "rad\rians\u202e"
    path = tmp_path / "odd\x1b]0;title\x07.wpilog"
    path.write_bytes(joint_log(q_name=name, q_unit=unit))
    status, out, err = run(capsys, "log-info", path)
    assert (status, err) == (0, "")
    assert not {c for c in out if not c.isprintable() and c != "\n"}, out
    for shown in (shown_name(name), shown_name(unit), shown_name(str(path))):
        assert shown in out
