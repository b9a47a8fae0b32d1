"""SysId logs as teams record them: lengths in metres, velocity-only routines, several motors, a test run twice,
the log's own time stamps, the logged velocity's lag.

Every log is written with robotpy-wpiutil's writer from a simple motor in closed form
(tests/support/sysid_motor_logs.py); values are checked against that closed form, never against jointid.
"""

import math

import numpy as np
import pytest
from support.sysid_motor_logs import GAINS, TESTS, MotorRoutine, motion, run_starts, write_motor_log

from jointid.logs.conventions import EntryMap
from jointid.logs.request import LoadRequest, load_joint_logs
from jointid.logs.table import LogError
from jointid.logs.timewindow import TimeWindow
from jointid.logs.velocity_lag import velocity_lag
from jointid.logs.wpilog import read_wpilog_table, read_wpilog_tables, wpilog_info
from jointid.studies.sysid import fit_sysid_runs

wpiutil = pytest.importorskip("wpiutil")

TEST_NAMES = [test for test, _ in TESTS]


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    """The motor's routine logged four ways: in metres with a lagging velocity, velocity only, two motors (one
    with a space in its name) with quasistatic-forward run twice, and with a test too short to fit."""
    folder = tmp_path_factory.mktemp("sysid-reading")
    other = {"kS": 0.2, "kV": 2.7, "kA": 0.35}
    return {
        "metres": write_motor_log(folder / "metres.wpilog", MotorRoutine(delay=0.113)),
        "velocity": write_motor_log(folder / "velocity.wpilog", MotorRoutine(position_unit=None)),
        "two": write_motor_log(folder / "two.wpilog", MotorRoutine(motors={"left": GAINS, "Moteur Droite": other},
                                                                   repeat_first=1.2)),
        "short": write_motor_log(folder / "short.wpilog", MotorRoutine(short={"dynamic-reverse": 12})),
    }


def test_a_length_is_read_in_metres_as_a_linear_coordinate(logs):
    table = read_wpilog_table(logs["metres"])
    assert dict(table.units) == {"q": "meters", "qd": "meters"} and table.linear
    assert table.position_source == "logged"
    # The first test's positions are the logged metres themselves: no factor of 2 pi, none of anything.
    name, rows = table.runs[0]
    start = run_starts(MotorRoutine(delay=0.113))[0]
    q, _ = motion("quasistatic-forward", 1, (table.stamps[rows] - 15) * 1e-6 - start)  # written 15 us after
    np.testing.assert_allclose(table.columns["q"][rows], q, atol=1e-6)


def test_a_length_is_fitted_with_no_gravity_and_its_gains_are_per_metre(logs):
    pooled = fit_sysid_runs(load_joint_logs(LoadRequest(str(logs["metres"]), wpilog=True)), sensitivity=False)
    assert pooled.runs[0].result.model.names == ("kA", "kV", "kS")  # no cos(q) of metres
    assert pooled.params["kV"] == pytest.approx(GAINS["kV"], rel=0.02)
    assert pooled.params["kS"] == pytest.approx(GAINS["kS"], rel=0.15)


def test_a_model_with_gravity_is_refused_on_metres(logs):
    from jointid.model.terms import model_named

    found = load_joint_logs(LoadRequest(str(logs["metres"]), wpilog=True))
    with pytest.raises(LogError, match=r"gravity term takes cos\(q\), and q here is a length in metres"):
        fit_sysid_runs(found, model_named("coulomb+angle-offset"))


def test_an_angle_unit_over_a_length_is_refused(logs):
    with pytest.raises(LogError, match="is in 'Meter', a length, not an angle; leave --units out"):
        read_wpilog_table(logs["metres"], units="rotations")


def test_the_logged_velocitys_lag_is_measured_within_a_fifth_of_a_step(logs):
    table = read_wpilog_table(logs["metres"])
    assert table.velocity_lag_s == pytest.approx(0.113, abs=0.004)  # the delay it was written with; steps of 20 ms
    assert any("lags the position's derivative by 113 ms" in note for note in table.sysid_notes)
    assert table.origin["velocity_lag_s"] == table.velocity_lag_s


def test_velocity_lag_of_a_closed_form_delay_and_of_none():
    # q = sin(2 pi f t) + t^2/5, v = its derivative delayed by d: the estimate finds d between grid steps.
    t = np.cumsum(np.full(400, 0.02))
    for delay in (0.0, 0.047, 0.21):
        q = np.sin(2 * math.pi * 0.7 * t) + t ** 2 / 5
        v = 2 * math.pi * 0.7 * np.cos(2 * math.pi * 0.7 * (t - delay)) + 2 * (t - delay) / 5
        assert velocity_lag(t, q, v, [slice(0, 200), slice(200, 400)]) == pytest.approx(delay, abs=0.002)


def test_a_velocity_only_routine_integrates_its_velocity(logs):
    table = read_wpilog_table(logs["velocity"])
    assert table.position_source == "integrated velocity" and table.velocity_lag_s is None
    assert "qd" not in table.columns  # its derivatives are estimated from q, which is the velocity integrated
    name, rows = table.runs[2]
    assert name == "dynamic-forward"
    start = run_starts(MotorRoutine(position_unit=None))[2]
    q, _ = motion("dynamic-forward", 1, table.stamps[rows] * 1e-6 - start)
    integrated = table.columns["q"][rows] - table.columns["q"][rows.start]
    np.testing.assert_allclose(integrated, q - q[0], atol=2e-3 * np.max(np.abs(q)))  # trapezoids at 20 ms
    assert any("velocity's lag behind the position cannot be checked" in note for note in table.sysid_notes)
    pooled = fit_sysid_runs(load_joint_logs(LoadRequest(str(logs["velocity"]), wpilog=True)), sensitivity=False)
    assert pooled.runs[0].result.model is not None and "kG" not in pooled.params
    assert pooled.params["kV"] == pytest.approx(GAINS["kV"], rel=0.02)


def test_several_motors_are_pooled_and_each_can_be_chosen(logs):
    tables = read_wpilog_tables(logs["two"])
    assert [t.routine.motor for t in tables] == ["Moteur Droite", "left"]
    found = load_joint_logs(LoadRequest(str(logs["two"]), wpilog=True))
    assert len(found) == 2 * 5 and found[0].name == "Moteur Droite quasistatic-forward #1"
    note = tables[0].sysid_notes[0]
    assert "pooled as one mechanism" in note and "--sysid-motor 'Moteur Droite'" in note
    one = load_joint_logs(LoadRequest(str(logs["two"]), wpilog=True, sysid_motor="Moteur Droite"))
    assert [log.name for log in one] == ["quasistatic-forward #1", "quasistatic-forward #2", *TEST_NAMES[1:]]
    pooled = fit_sysid_runs(one, sensitivity=False)
    assert pooled.params["kV"] == pytest.approx(2.7, rel=0.02)  # that motor's own gain, not the other's 2.5
    with pytest.raises(LogError, match="--sysid-motor 'right': the log has no SysId motor or routine"):
        read_wpilog_tables(logs["two"], motor="right")
    with pytest.raises(LogError, match="has 2 motors"):
        read_wpilog_table(logs["two"])


def test_a_test_run_twice_is_two_runs_split_at_the_gap(logs):
    routine = MotorRoutine(motors={"left": GAINS, "Moteur Droite": GAINS}, repeat_first=1.2)
    table = read_wpilog_tables(logs["two"], motor="left")[0]
    names = [name for name, _ in table.runs]
    assert names == ["quasistatic-forward #1", "quasistatic-forward #2", *TEST_NAMES[1:]]
    starts = run_starts(routine)
    for (name, rows), start in zip(table.runs, starts):
        assert abs(table.columns["t"][rows.start] - start) < 1e-3, name  # the log's own seconds
    first, second = table.runs[0][1], table.runs[1][1]
    assert table.columns["t"][first.stop - 1] < starts[0] + 1.3 < starts[1] <= table.columns["t"][second.start]
    first_only = read_wpilog_tables(logs["two"], motor="left", repeats="first")[0]
    assert [name for name, _ in first_only.runs] == ["quasistatic-forward #1", *TEST_NAMES[1:]]
    assert first_only.left_out[0][0] == "quasistatic-forward #2" and "a repeat" in first_only.left_out[0][1]


def test_log_info_counts_in_the_logs_own_seconds_and_names_repeats(logs):
    info = wpilog_info(logs["two"])
    document = info.to_dict()
    runs = document["sysid"][0]["runs"]
    assert [run["name"] for run in runs] == ["quasistatic-forward #1", "quasistatic-forward #2", *TEST_NAMES[1:]]
    starts = run_starts(MotorRoutine(motors={"left": GAINS, "Moteur Droite": GAINS}, repeat_first=1.2))
    np.testing.assert_allclose([run["start_s"] for run in runs], starts, atol=1e-3)
    battery = next(e for e in document["entries"] if e["name"] == "/SystemStats/BatteryVoltage")
    assert battery["first_s"] == pytest.approx(0.1)  # written before the routine: its own time, not shifted


def test_a_window_read_off_log_info_selects_that_test(logs):
    starts = run_starts(MotorRoutine())
    window = TimeWindow(starts[2] - 0.5, starts[3] - 0.5)  # around dynamic-forward, in the log's own seconds
    found = load_joint_logs(LoadRequest(str(logs["short"]), wpilog=True, time_window=window))
    assert [log.name for log in found] == ["dynamic-forward"]
    with pytest.raises(LogError, match=r"no samples in the training window 1:2 s; the samples span 20 to"):
        load_joint_logs(LoadRequest(str(logs["short"]), wpilog=True, time_window=TimeWindow(1, 2)))


def test_an_exclusion_counts_in_the_logs_own_seconds(logs):
    from jointid.estimation.exclusion import ExclusionRequest

    found = load_joint_logs(LoadRequest(str(logs["metres"]), wpilog=True))
    start = run_starts(MotorRoutine(delay=0.113))[0]
    pooled = fit_sysid_runs(found, exclusion=ExclusionRequest(robust=False, by_hand=((start + 1.0, start + 2.0),)),
                            sensitivity=False)
    left = pooled.runs[0].exclusions
    t = pooled.runs[0].training.data.t
    assert left.pushes[(t >= start + 1.0) & (t <= start + 2.0)].all()
    assert not left.pushes[t > start + 2.1].any()
    with pytest.raises(LogError, match="--exclude 1:2 holds no sample of any test; the tests span 20 to"):
        fit_sysid_runs(found, exclusion=ExclusionRequest(by_hand=((1.0, 2.0),)), sensitivity=False)


def test_a_test_too_short_is_left_out_and_named(logs):
    table = read_wpilog_table(logs["short"])
    assert [name for name, _ in table.runs] == TEST_NAMES[:3]
    assert table.left_out[0][0] == "dynamic-reverse" and "too short to fit: 12 samples" in table.left_out[0][1]
    assert any(note.startswith("Left out: dynamic-reverse, too short") for note in table.sysid_notes)


def test_an_entry_map_naming_a_string_entry_is_refused(logs):
    with pytest.raises(LogError, match="entry 'sysid-test-state-drive' holds string, not numbers"):
        read_wpilog_table(logs["metres"], EntryMap.parse("q=sysid-test-state-drive,tau=voltage-left-drive"))


def test_a_state_recorded_between_two_samples_ends_a_run_with_no_gap():
    from jointid.logs.wpilog import test_runs

    # Samples every 20 ms without a pause; the routine records "none" once between samples 49 and 50 and starts
    # the same test again: two runs, though no sample took the "none" and no time gap shows it.
    samples = np.arange(100) * 20_000
    times = np.concatenate([samples[:50] + 45, [samples[49] + 10_000], samples[50:] + 45])
    states = np.array(["quasistatic-forward"] * 50 + ["none"] + ["quasistatic-forward"] * 50, dtype=object)
    runs = test_runs(times, states, samples)
    assert [(test, rows.start, rows.stop) for test, rows in runs] == [
        ("quasistatic-forward", 0, 50), ("quasistatic-forward", 50, 100)]
    steady = np.array(["quasistatic-forward"] * 100, dtype=object)  # the same without the "none": one run
    assert [(rows.start, rows.stop) for _, rows in test_runs(samples + 45, steady, samples)] == [(0, 100)]
