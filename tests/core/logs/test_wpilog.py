"""WPILib data logs: read through robotpy-wpiutil, put on one time base, a SysId routine's tests fitted as runs.

The logs are written with robotpy-wpiutil's own writer, but for the damaged ones (and big entry ids), written byte
by byte from the format's specification (tests/support/datalog_bytes.py); the SysId routine comes from an
independent simulation of the arm behind known gains (tests/support/sysid_arm.py), and the gains are checked against
those numbers.
"""

import math

import numpy as np
import pytest
from support.sysid_arm import (
    ADVANTAGEKIT_NAMES,
    GAINS,
    TESTS,
    routine_samples,
    write_routine_log,
)

from jointid.logs.conventions import EntryMap
from jointid.logs.request import LoadRequest, load_joint_log, load_joint_logs
from jointid.logs.table import LogError
from jointid.logs.wpilog import EXTRA_HINT, angle_unit, read_wpilog_table, wpilog_info
from jointid.studies.sysid import fit_sysid_runs

wpiutil = pytest.importorskip("wpiutil")
pytest.importorskip("wpiutil.log")  # its writer's entries: a submodule the package does not import itself

@pytest.fixture(scope="module")
def routine(tmp_path_factory):
    """The simulated routine written three ways: SysId's names in rotations and in radians, AdvantageKit's."""
    folder = tmp_path_factory.mktemp("sysid")
    samples = routine_samples()
    return {
        "samples": samples,
        "rotations": write_routine_log(folder / "arm.wpilog", samples),
        "radians": write_routine_log(folder / "arm-radians.wpilog", samples, units="radians"),
        "advantagekit": write_routine_log(folder / "akit.wpilog", samples, units="radians", names=ADVANTAGEKIT_NAMES,
                                          metadata=False, extra_entries=False),
    }


@pytest.fixture(scope="module")
def pooled(routine):
    """The rotations log's tests fitted together."""
    return fit_sysid_runs(load_joint_logs(LoadRequest(str(routine["rotations"]), wpilog=True, window=None)))


def test_a_sysid_log_is_split_into_its_four_tests_in_order(routine):
    logs = load_joint_logs(LoadRequest(str(routine["rotations"]), wpilog=True, window=None))
    assert [log.name for log in logs] == [test for test, _ in TESTS]
    for log, samples in zip(logs, routine["samples"]):
        # Every sample of the test is read but at most one at each edge (the state is recorded after the values).
        assert len(samples.t) - 2 <= log.rows <= len(samples.t)
        logged = samples.q[: log.rows + 2]
        assert np.min(np.abs(log.source.columns["q"][0] - logged)) < 1e-9


def test_the_pooled_fit_gives_the_arms_gains(pooled):
    # A SysId log's effort is the motor's voltage: the model's parameters are WPILib's gains by name.
    for name in ("kA", "kG", "kV", "kS"):
        value = GAINS[name]
        error = abs(pooled.params[name] - value)
        assert error <= max(0.03 * value, 3 * pooled.bse[name]), (name, pooled.params[name], pooled.bse[name])
    assert abs(pooled.params["q0"] - GAINS["offset"]) < 0.01


def test_positions_in_rotations_and_in_radians_give_the_same_gains(routine, pooled):
    radians = fit_sysid_runs(load_joint_logs(LoadRequest(str(routine["radians"]), wpilog=True, window=None)))
    for name in pooled.shared:
        assert radians.params[name] == pytest.approx(pooled.params[name], rel=1e-6, abs=1e-9)


def test_an_entry_map_reads_the_same_routine_under_advantagekit_names(routine, pooled):
    names = ADVANTAGEKIT_NAMES
    entries = EntryMap.parse(f"q={names['position']},qd={names['velocity']},tau={names['voltage']},"
                             f"state={names['state']}")
    request = LoadRequest(str(routine["advantagekit"]), wpilog=True, window=None, entries=entries, units="radians")
    mapped = fit_sysid_runs(load_joint_logs(request))
    assert [run.name for run in mapped.runs] == [test for test, _ in TESTS]
    for name in pooled.shared:
        assert mapped.params[name] == pytest.approx(pooled.params[name], rel=1e-6, abs=1e-9)


def test_without_metadata_or_units_the_angle_unit_is_asked_for(routine):
    names = ADVANTAGEKIT_NAMES
    entries = EntryMap.parse(f"q={names['position']},tau={names['voltage']}")
    with pytest.raises(LogError, match="names no unit in its metadata; say which with --units"):
        read_wpilog_table(routine["advantagekit"], entries)


def test_entries_go_on_the_position_entrys_time_base(tmp_path):
    # q every 10 ms; the voltage 3 ms later each time and linear in time, so interpolation gives it exactly;
    # a gap of 0.5 s in the voltage leaves the q samples inside it out.
    path = tmp_path / "base.wpilog"
    writer = wpiutil.DataLogWriter(str(path))
    position = wpiutil.log.DoubleLogEntry(writer, "/Arm/Position", "Radian", 1)
    volts = wpiutil.log.DoubleLogEntry(writer, "/Arm/Volts", 1)
    stamps = np.arange(100_000, 2_100_000, 10_000)
    for stamp in stamps:
        position.append(0.001 * (stamp / 1e4), int(stamp))
        if not 1_000_000 < stamp < 1_500_000:
            volts.append(2.0 + 3.0 * (stamp + 3000) * 1e-6, int(stamp + 3000))
    writer.flush()
    writer.stop()
    table = read_wpilog_table(path, EntryMap.parse("q=/Arm/Position,tau=/Arm/Volts"))
    kept = stamps[(stamps >= 103_000) & ~((stamps > 1_000_000) & (stamps < 1_500_000 + 3000))]
    np.testing.assert_array_equal(table.stamps, kept)
    np.testing.assert_allclose(table.columns["tau"], 2.0 + 3.0 * kept * 1e-6, rtol=1e-12)
    np.testing.assert_allclose(table.columns["t"], kept * 1e-6)  # the log's own time stamps, in seconds


@pytest.mark.parametrize(("name", "rate", "unit", "factor"), [
    ("Rotation", False, "rotations", 1.0), ("Rotation per Second", True, "rotations", 1.0),
    ("turn", False, "rotations", 1.0), ("turns_per_second", True, "rotations", 1.0),
    ("Radian", False, "radians", 1.0), ("rad/s", True, "radians", 1.0), ("Degree", False, "degrees", 1.0),
    ('{"unit": "rotations"}', False, None, 1.0), ("rpm", True, "rotations", 1 / 60), ("Meter", False, None, 1.0),
])
def test_unit_names_of_java_and_cpp(name, rate, unit, factor):
    from jointid.logs.wpilog import unit_text

    text = unit_text(name)
    assert angle_unit(text, rate) == (unit if not name.startswith("{") else "rotations", pytest.approx(factor))


def test_log_info_lists_entries_units_and_the_four_tests(routine):
    info = wpilog_info(routine["rotations"])
    entries = {entry.name: entry for entry in info.entries}
    position = entries["position-arm-motor-arm"]
    assert position.unit == "Rotation" and position.type == "double"
    assert position.records == sum(len(s.t) for s in routine["samples"])
    assert [test for test, *_ in info.runs["arm"]] == [test for test, _ in TESTS]
    assert len(info.routines) == 1 and info.routines[0].motor == "arm-motor"


def test_a_log_cut_short_is_refused(routine, tmp_path):
    data = routine["rotations"].read_bytes()
    cut = tmp_path / "cut.wpilog"
    cut.write_bytes(data[: len(data) - 7])
    with pytest.raises(LogError, match="cut short"):
        load_joint_logs(LoadRequest(str(cut), wpilog=True))


def test_a_single_log_request_for_a_sysid_log_says_it_holds_runs(routine):
    with pytest.raises(LogError, match="SysId log of 4 test runs"):
        load_joint_log(LoadRequest(str(routine["rotations"]), wpilog=True))


def test_without_robotpy_wpiutil_one_line_names_the_extra(routine, monkeypatch):
    import jointid.logs.wpilog as wpilog

    monkeypatch.setattr(wpilog, "_reader_class", lambda: None)
    with pytest.raises(LogError) as raised:
        wpilog_info(routine["rotations"])
    assert EXTRA_HINT in str(raised.value) and "jointid[wpilib]" in str(raised.value)
    assert "\n" not in str(raised.value)


def test_degrees_convert_by_pi_over_180(tmp_path):
    path = tmp_path / "deg.wpilog"
    writer = wpiutil.DataLogWriter(str(path))
    position = wpiutil.log.DoubleLogEntry(writer, "q", "Degree", 1)
    effort = wpiutil.log.DoubleLogEntry(writer, "v", 1)
    for k in range(50):
        position.append(float(k), 1000 + 10_000 * k)
        effort.append(1.0, 1000 + 10_000 * k)
    writer.flush()
    writer.stop()
    table = read_wpilog_table(path, EntryMap.parse("q=q,tau=v"))
    np.testing.assert_allclose(table.columns["q"], np.arange(50) * math.pi / 180)


def test_the_library_fits_a_data_log_as_the_command_line_does(routine):
    """jointid.fit_wpilog: a SysId log's pooled gains within 3 % or 3 SEs of the simulated arm's (as above, from
    the library's one call), an AdvantageKit log through an entry map, and bad arguments named."""
    import jointid

    arm = jointid.fit_wpilog(routine["rotations"])
    assert arm.names == tuple(test for test, _ in TESTS)
    for name in ("kA", "kG", "kV", "kS"):
        assert abs(arm.params[name] - GAINS[name]) <= max(0.03 * GAINS[name], 3 * arm.bse[name]), name
    names = ADVANTAGEKIT_NAMES
    mapped = jointid.fit_wpilog(routine["advantagekit"], units="radians", sensitivity=False,
                                entry=f"q={names['position']},tau={names['voltage']},state={names['state']}")
    for name in ("kA", "kG", "kV", "kS"):
        assert abs(mapped.params[name] - GAINS[name]) <= max(0.03 * GAINS[name], 3 * mapped.bse[name]), name
    with pytest.raises(ValueError, match="units"):
        jointid.fit_wpilog(routine["rotations"], units="furlongs")
    with pytest.raises(ValueError, match="QUANTITY=NAME"):
        jointid.fit_wpilog(routine["rotations"], entry="position")
    with pytest.raises(LogError, match="nowhere.wpilog"):
        jointid.fit_wpilog("nowhere.wpilog")


# ---------------------------------------------------------------------------------------------- damaged logs
# Written byte by byte from the format's specification (tests/support/datalog_bytes.py), not by robotpy-wpiutil.

from support.datalog_bytes import damaged_logs, joint_log  # noqa: E402

from jointid.logs.wpilog import read_entries  # noqa: E402

DAMAGED = damaged_logs()


@pytest.mark.parametrize("case", sorted(DAMAGED))
def test_a_damaged_log_is_one_line_naming_the_file_and_the_fault(tmp_path, case):
    data, word = DAMAGED[case]
    path = tmp_path / f"{case}.wpilog"
    path.write_bytes(data)
    with pytest.raises(LogError) as caught:
        read_entries(path, lambda name, kind: True, count_all=True)  # every record decoded, as fit and log-info may
    message = str(caught.value)
    assert message.startswith(f"{path}: is damaged: ") and "\n" not in message and word in message, message


def test_the_library_raises_a_value_error_for_a_damaged_log(tmp_path):
    from jointid import fit_wpilog

    path = tmp_path / "not-utf8.wpilog"
    path.write_bytes(DAMAGED["metadata-not-utf8"][0])
    with pytest.raises(ValueError, match="metadata in the Start record of entry id 1 .* is not UTF-8"):
        fit_wpilog(path, entry="q=q,tau=tau")


def test_entry_ids_of_2_to_the_31_and_more_are_a_whole_log(tmp_path):
    # Entry ids are unsigned 32-bit numbers (the specification); the reader hands them over as signed ones.
    path = tmp_path / "big-ids.wpilog"
    data = joint_log(q_id=2**31 + 5, tau_id=2**32 - 1)
    path.write_bytes(data)
    table = read_wpilog_table(path, EntryMap.parse("q=q,tau=tau"), units="radians")
    samples = 40
    k = np.arange(samples)
    assert np.array_equal(table.columns["q"], 0.5 * (k / samples) ** 2)
    assert np.array_equal(table.columns["tau"], 1.0 + 0.01 * k)
    path.write_bytes(data[:-3])  # and one cut inside its last record is still seen
    with pytest.raises(LogError, match="cut short or damaged"):
        read_wpilog_table(path, EntryMap.parse("q=q,tau=tau"), units="radians")


def test_an_id_started_again_as_another_type_is_not_decoded_as_the_first(tmp_path):
    from support.datalog_bytes import start, string

    path = tmp_path / "restarted.wpilog"
    path.write_bytes(joint_log() + start(1, "q", "string", "", 9_000_000) + string(1, 9_000_001, "hi"))
    entries, series = read_entries(path, lambda name, kind: True)
    assert len(series["q"].values) == 40 and entries["q"].type == "double"  # the string record is not q's
