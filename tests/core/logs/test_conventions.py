"""Logs as robots write them: column names and maps, the angle's zero and direction, wrapped and far-off angles.

Expected values are computed here with numpy from a closed-form joint, never from jointid's own output: the
log is written in the robot's convention (angle a = s (q - offset), torque positive toward increasing a) and
the fit must give back the joint's I, h, B, as numpy.linalg.lstsq does on the true columns.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from support.conventions_support import G, OFFSETS, TRUE, joint, logged, lstsq, wrap

from jointid.logs.arrays import read_arrays
from jointid.logs.conventions import AngleConvention, ColumnMap, ColumnMapError, quantity_of
from jointid.logs.csv_reader import load_log, read_table
from jointid.logs.request import LoadRequest, load_joint_log
from jointid.logs.table import LogError
from jointid.studies.log_fit import fit_log

def write_csv(path, header, *columns):
    np.savetxt(path, np.column_stack(columns), delimiter=",", header=header, comments="", fmt="%.17g")
    return path


def params(fit):
    return np.array([fit.params[name] for name in ("I", "h", "B")])


# ------------------------------------------------------------------------------------------ column names


@pytest.mark.parametrize("name, quantity", [
    ("time", "t"), ("Timestamp", "t"), ("T", "t"), ("position", "q"), ("POS", "q"), ("angle", "q"),
    ("velocity", "qd"), ("vel", "qd"), ("acceleration", "qdd"), ("accel", "qdd"), ("torque", "tau"), ("Effort", "tau"),
])
def test_names_loggers_use_are_recognised(name, quantity):
    assert quantity_of(name) == quantity


@pytest.mark.parametrize("name", ["position_rad", "position_deg", "time_s", "time_ms", "velocity [rad/s]", "tau_cmd",
                                  "positions", "effort2", "current", ""])
def test_suffixed_and_other_names_are_not_read_unasked(name):
    assert quantity_of(name) is None


def test_suffixed_names_are_suggested_as_a_map(tmp_path):
    path = tmp_path / "units.csv"
    path.write_text("time_s,position_deg,velocity_deg_s,torque_nm,tau_cmd\n0,0,0,1,1\n")
    with pytest.raises(LogError) as caught:
        read_table(path)
    # tau has two candidates (torque_nm and tau_cmd): which is measured cannot be told, so it is left out.
    assert str(caught.value) == (
        f"{path}, row 1: missing required column 'q' in the header; to read 'time_s', 'position_deg', "
        "'velocity_deg_s' (suffixed names are not read unasked), give --columns "
        "t=time_s,q=position_deg,qd=velocity_deg_s (and --degrees)")
    with pytest.raises(LogError, match=r"^arrays: no q column; .* give columns=\{'q': 'angle_rad'\}$"):
        read_arrays({"t": [0.0], "angle_rad": [0.0], "tau": [1.0]})
    # A second time base beside t is left alone, as before.
    table = read_arrays({"time_s": [0.0, 1.0], "t": [0.0, 1.0], "q": [0.0, 0.1], "tau": [1.0, 1.0]})
    assert table.ignored == ("time_s",) and table.notes == ()


def test_robot_header_is_read_and_noted(tmp_path):
    t = np.arange(200) * 0.01
    q, qd, qdd, tau = joint(t)
    path = write_csv(tmp_path / "robot.csv", "Time,position,velocity,accel,effort,current", t, q, qd, qdd, tau,
                     0 * t)
    log = load_log(path)
    # Read as written: no conversion, the values are the file's.
    assert np.array_equal(log.data.q, q) and np.array_equal(log.data.tau, tau) and np.array_equal(log.data.qdd, qdd)
    assert log.notes[0] == (f"{path}: columns read as t=Time, q=position, qd=velocity, qdd=accel, "
                            "tau=effort.")
    assert log.notes[1] == f"{path}: ignored columns 'current'."
    assert log.conventions["columns"] == {"t": "Time", "q": "position", "qd": "velocity", "qdd": "accel",
                                          "tau": "effort"}


def test_canonical_names_give_no_note_and_default_conventions(tmp_path):
    t = np.arange(50) * 0.01
    q, qd, qdd, tau = joint(t)
    log = load_log(write_csv(tmp_path / "plain.csv", "t,Q,qd,qdd,tau", t, q, qd, qdd, tau))
    assert log.notes == ()
    assert log.conventions == {"columns": {"t": "t", "q": "Q", "qd": "qd", "qdd": "qdd", "tau": "tau"},
                               "zero": "right", "clockwise": False, "sign": 1, "offset_rad": 0.0,
                               "q_from_log": "q = logged q", "unwrapped_jumps": 0, "wrapped_range": None,
                               "turns_removed": 0}


def test_two_columns_for_one_quantity_are_refused_naming_both(tmp_path):
    path = tmp_path / "both.csv"
    path.write_text("t,q,position,tau\n0,0,0,1\n0.1,0,0,1\n")
    with pytest.raises(LogError) as caught:
        read_table(path)
    assert str(caught.value) == (f"{path}, row 1: columns 2 ('q') and 3 ('position') both give q; keep one, or "
                                 "choose one with --columns q=NAME")
    with pytest.raises(LogError, match=r"columns 'torque' and 'effort' both give tau; keep one, or choose one "
                                       r"with columns=\{'tau': 'NAME'\}"):
        read_arrays({"q": [0.0], "torque": [1.0], "effort": [1.0]})


def test_messages_name_the_column_as_the_log_does(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("time,position,velocity,torque\n0,0,0,1\n0.1,nan,0,1\n0.2,0,0,1\n")
    with pytest.raises(LogError, match=r"bad.csv, row 3, column 2 \(position\): NaN is not a measurement$"):
        read_table(path)
    path.write_text("time,position,velocity,torque\n0,0,0,1\n0.1,0,x,1\n0.2,0,0,1\n")
    with pytest.raises(LogError, match=r"bad.csv, row 3, column 3 \(velocity\): 'x' is not a number$"):
        read_table(path)
    with pytest.raises(LogError, match=r"^arrays, sample 1, column 'angle': NaN is not a measurement$"):
        fit_log({"t": [0.0, 0.1, 0.2, 0.3], "angle": [0.0, float("nan"), 0.0, 0.0], "tau": [1.0] * 4})


def test_the_same_name_twice_keeps_its_message(tmp_path):
    path = tmp_path / "twice.csv"
    path.write_text("t,q,tau,q\n0,0,1,0\n")
    with pytest.raises(LogError, match=r"row 1: column 'q' appears twice \(columns 2 and 4\)$"):
        read_table(path)


def test_a_map_names_any_column_and_wins_over_names(tmp_path):
    t = np.arange(100) * 0.01
    q, qd, qdd, tau = joint(t)
    # 'position' is the commanded angle here; the measured one is 'posn'.
    path = write_csv(tmp_path / "mapped.csv", "stamp,position,posn,vel_meas,a,tau_cmd,torque",
                     t, 0 * q, q, qd, qdd, 0 * tau, tau)
    log = load_joint_log(LoadRequest(str(path), columns=ColumnMap.parse("t=stamp,q=posn,qd=vel_meas,qdd=a")))
    assert np.array_equal(log.data.q, q) and np.array_equal(log.data.qd, qd) and np.array_equal(log.data.tau, tau)
    assert log.notes[0].endswith("columns read as t=stamp, q=posn, qd=vel_meas, qdd=a, tau=torque.")
    assert log.ignored == ("position", "tau_cmd")


def test_a_map_naming_a_missing_column_is_one_line(tmp_path):
    path = tmp_path / "log.csv"
    path.write_text("time,position,velocity,torque\n0,0,0,1\n")
    with pytest.raises(LogError) as caught:
        read_table(path, column_map=ColumnMap.parse("q=posn"))
    assert str(caught.value) == (f"{path}, row 1: --columns q=posn: the log has no column 'posn'; its columns are "
                                 "time, position, velocity, torque")


@pytest.mark.parametrize("text, message", [
    ("pos=position", "unknown quantity 'pos' in pos=position; the quantities are t, q, qd, qdd, tau"),
    ("q", "'q' is not QUANTITY=NAME; give e.g. t=time,q=position,tau=effort"),
    ("q=", "q= names no column"),
    ("q=a,q=b", "q is given twice (q=a and q=b)"),
    ("q=a,tau=A", "column 'A' is given for both q and tau"),
])
def test_bad_maps_are_refused(text, message):
    with pytest.raises(ColumnMapError) as caught:
        ColumnMap.parse(text)
    assert str(caught.value) == message


def test_arrays_take_names_and_maps():
    t = np.arange(100) * 0.01
    q, qd, qdd, tau = joint(t)
    table = read_arrays({"timestamp": t, "angle": q, "velocity": qd, "torque": tau})
    assert table.notes == ("columns read as t=timestamp, q=angle, qd=velocity, tau=torque.",)
    assert np.array_equal(table.columns["q"], q)
    fit = fit_log({"time": t, "posn": q, "vel": qd, "acc": qdd, "tau": tau}, columns={"q": "posn", "qdd": "acc"},
                  cutoff=0)
    np.testing.assert_allclose(params(fit), lstsq(q, qd, qdd, tau), rtol=1e-9)
    assert fit.notes()[0] == "arrays: columns read as t=time, q=posn, qd=vel, qdd=acc, tau=tau."
    with pytest.raises(LogError, match="columns q=posn: the log has no column 'posn'; its columns are q, tau"):
        fit_log({"q": q, "tau": tau}, columns="q=posn")
    with pytest.raises(ColumnMapError, match="^columns: unknown quantity 'angle'"):
        fit_log({"q": q, "tau": tau}, columns={"angle": "q"})
    with pytest.raises(TypeError, match="columns must be a mapping"):
        fit_log({"q": q, "tau": tau}, columns=3)
    with pytest.raises(ValueError, match="zero must be one of right, up, left, down; got 'below'"):
        fit_log({"q": q, "tau": tau}, zero="below")


# ------------------------------------------------------------------------------------------ zero and direction


@pytest.mark.parametrize("clockwise", [False, True])
@pytest.mark.parametrize("zero", list(OFFSETS))
def test_every_convention_gives_the_joint_back(zero, clockwise):
    t = np.arange(1200) * 0.005
    q, qd, qdd, tau = joint(t)
    a, ad, add, tau_a = logged(t, zero, clockwise)
    fit = fit_log({"time": t, "position": a, "velocity": ad, "acceleration": add, "torque": tau_a}, zero=zero,
                  clockwise=clockwise, cutoff=0)
    np.testing.assert_allclose(fit.training.data.q, q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(fit.training.data.qd, qd, rtol=0, atol=1e-12)
    np.testing.assert_allclose(fit.training.data.tau, tau, rtol=0, atol=1e-12)
    np.testing.assert_allclose(params(fit), lstsq(q, qd, qdd, tau), rtol=1e-8)
    np.testing.assert_allclose(params(fit), TRUE, rtol=1e-8)
    turning = "clockwise" if clockwise else "counter-clockwise"
    conversion = [note for note in fit.notes() if note.startswith("arrays: angle 0 pointing")]
    if zero == "right" and not clockwise:
        assert conversion == []
    else:
        assert conversion[0].startswith(f"arrays: angle 0 pointing {zero}, {turning}: q = ")
        assert ("qd, qdd and tau change sign" in conversion[0]) == clockwise
    assert fit.training.conventions["zero"] == zero and fit.training.conventions["sign"] == (-1 if clockwise else 1)


def test_a_wrong_convention_is_not_silently_right():
    t = np.arange(1200) * 0.005
    a, ad, add, tau_a = logged(t, "right", clockwise=True)
    arrays = {"t": t, "q": a, "qd": ad, "qdd": add, "tau": tau_a}
    wrong = params(fit_log(arrays, cutoff=0))  # read counter-clockwise: q = -q_true, cos unchanged, qd, qdd, tau flip
    np.testing.assert_allclose(wrong, [TRUE[0], -TRUE[1], TRUE[2]], rtol=1e-8)
    wrong = params(fit_log(arrays, zero="left", clockwise=True, cutoff=0))  # cos q changes sign
    np.testing.assert_allclose(wrong, [TRUE[0], -TRUE[1], TRUE[2]], rtol=1e-8)


@pytest.mark.parametrize("zero", ["down", "up"])
def test_about_the_vertical_the_direction_cannot_matter(zero):
    # Mirroring the joint about the vertical (gravity's axis) is a symmetry: with zero down or up, reading a
    # clockwise log as counter-clockwise gives q' = -q - pi (or -q + pi), cos q' = -cos q, and qd, qdd, tau
    # flipped, so every term flips and the fit is the same. The torque's sign must follow the angle's for this.
    t = np.arange(1200) * 0.005
    a, ad, add, tau_a = logged(t, zero, clockwise=True)
    arrays = {"t": t, "q": a, "qd": ad, "qdd": add, "tau": tau_a}
    np.testing.assert_allclose(params(fit_log(arrays, zero=zero, cutoff=0)), TRUE, rtol=1e-8)
    # Had tau kept its sign when the angle's direction was flipped, the fit would be the negated joint.
    flipped = {**arrays, "tau": -tau_a}
    np.testing.assert_allclose(params(fit_log(flipped, zero=zero, clockwise=True, cutoff=0)), -TRUE, rtol=1e-8)


@pytest.mark.parametrize("zero, clockwise, formula", [
    ("down", False, "q = position - pi/2"), ("up", False, "q = position + pi/2"), ("left", False, "q = position + pi"),
    ("right", True, "q = -position"), ("down", True, "q = -pi/2 - position"), ("up", True, "q = pi/2 - position"),
    ("left", True, "q = pi - position"),
])
def test_the_note_states_the_conversion(zero, clockwise, formula):
    convention = AngleConvention(zero, clockwise)
    assert convention.formula("position") == formula
    assert convention.note("position").startswith(f"angle 0 pointing {zero}, "
                                                  f"{'clockwise' if clockwise else 'counter-clockwise'}: {formula}")


def test_estimated_derivatives_follow_the_convention(tmp_path):
    # Only t, angle and torque: qd and qdd are estimated from the logged angle and must change sign with it.
    t = np.arange(2000) * 0.004
    q, qd, qdd, tau = joint(t)
    a, _, _, tau_a = logged(t, "up", clockwise=True)
    path = write_csv(tmp_path / "cw.csv", "time,angle,torque", t, a, tau_a)
    log = load_joint_log(LoadRequest(str(path), window=31, angle=AngleConvention("up", True)))
    keep = slice(15, len(t) - 15)  # away from the smoothing's polynomial ends
    np.testing.assert_allclose(log.data.q, q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(log.data.qd[keep], qd[keep], rtol=0, atol=1e-4)  # central differences: O(h^2)
    np.testing.assert_allclose(log.data.qdd[keep], qdd[keep], rtol=0, atol=1e-2)
    # with_window derives again in the same convention.
    np.testing.assert_allclose(log.with_window(41).data.qd[20:-20], qd[20:-20], rtol=0, atol=1e-4)


# ------------------------------------------------------------------------------------------ wrapped and far-off


@pytest.mark.parametrize("positive", [False, True])
def test_wrapped_csv_is_unwrapped_and_fits(tmp_path, positive):
    t = np.arange(3000) * 0.004
    q, qd, qdd, tau = joint(t, spin=2.0)  # about four turns
    a = wrap(q, positive=positive)
    path = write_csv(tmp_path / "wrapped.csv", "time,position,torque", t, a, tau)
    log = load_joint_log(LoadRequest(str(path), window=31))
    jumps = int(np.count_nonzero(np.abs(np.diff(a)) > np.pi))
    assert jumps >= 3
    # The first sample stays; every other differs from q by the same whole turns.
    shift = a[0] - q[0]
    np.testing.assert_allclose(log.data.q, q + shift, rtol=0, atol=1e-9)
    np.testing.assert_allclose(log.data.qd[15:-15], qd[15:-15], rtol=0, atol=1e-4)
    wrapped = "[0, 2 pi)" if positive else "(-pi, pi]"
    assert f"{path}: position is wrapped to {wrapped}: unwrapped (numpy.unwrap) at {jumps} jumps of nearly a full " \
           "turn between samples." in log.notes
    assert log.conventions["unwrapped_jumps"] == jumps and log.conventions["wrapped_range"] == wrapped
    assert np.array_equal(load_log(path, window=31).data.q, log.data.q)
    fit = fit_log(path, window=31, cutoff=0, model="plain")
    np.testing.assert_allclose(params(fit), lstsq(q, qd, qdd, tau), rtol=1e-4)


def test_wrapped_degrees_are_unwrapped_in_degrees(tmp_path):
    t = np.arange(2000) * 0.004
    q, qd, qdd, tau = joint(t, spin=-2.5)
    a = wrap(np.degrees(q), 360.0)
    path = write_csv(tmp_path / "deg.csv", "t,q,qd,qdd,tau", t, a, np.degrees(qd), np.degrees(qdd), tau)
    log = load_joint_log(LoadRequest(str(path), degrees=True))
    np.testing.assert_allclose(np.cos(log.data.q), np.cos(q), rtol=0, atol=1e-12)
    assert np.max(np.abs(np.diff(log.data.q))) < 0.1
    assert any("q is wrapped to (-180, 180]" in note for note in log.notes)


def test_wrapped_arrays_are_unwrapped():
    t = np.arange(3000) * 0.004
    q, qd, qdd, tau = joint(t, spin=2.0)
    fit = fit_log({"t": t, "q": wrap(q), "qd": qd, "qdd": qdd, "tau": tau}, cutoff=0, model="plain")
    np.testing.assert_allclose(fit.training.data.q, q, rtol=0, atol=1e-9)
    np.testing.assert_allclose(params(fit), TRUE, rtol=1e-8)
    assert any("logged q is wrapped to (-pi, pi]" in note for note in fit.notes())


@pytest.mark.parametrize("kind", ["dict", "DataFrame"])
def test_every_array_reader_unwraps_and_removes_far_off_turns(kind):
    """The library's arrays, as a dict or a pandas DataFrame, go through the same angle reading as a CSV or a bag:
    a wrapped angle is unwrapped and fits the joint; one 1e14 turns from zero loses its turns, keeping cos q
    (references: numpy's own; the far-off angle's lost digits stay lost, so its fit is not compared)."""
    pandas = pytest.importorskip("pandas")

    def read(columns):
        return fit_log(columns if kind == "dict" else pandas.DataFrame(columns), cutoff=0, model="plain",
                       sensitivity=False)

    t = np.arange(3000) * 0.004
    q, qd, qdd, tau = joint(t, spin=2.0)
    fit = read({"t": t, "q": wrap(q), "qd": qd, "qdd": qdd, "tau": tau})
    np.testing.assert_allclose(fit.training.data.q, q, rtol=0, atol=1e-9)
    np.testing.assert_allclose(params(fit), TRUE, rtol=1e-8)
    assert any("logged q is wrapped to (-pi, pi]" in note for note in fit.notes())
    stored, expected, qd, qdd, tau = far_off(t)
    fit = read({"t": t, "q": stored, "qd": qd, "qdd": qdd, "tau": tau})
    np.testing.assert_allclose(fit.training.data.q, expected, rtol=0, atol=1e-9)
    assert any("100000000000000 whole turns from zero" in note for note in fit.notes())


def test_a_swing_inside_the_range_or_a_real_jump_is_left_alone():
    t = np.arange(400) * 0.01
    q, qd, qdd, tau = joint(t)
    log = fit_log({"t": t, "q": q, "qd": qd, "qdd": qdd, "tau": tau}, cutoff=0).training
    assert np.array_equal(log.data.q, q) and log.notes == ()
    # A jump of 0.6 turn is not a wrap: the joint (or the logger) really did that; nothing is undone.
    jumped = np.where(t > 2, q + 1.2 * np.pi, q) - 1.9
    assert np.ptp(jumped) < 2 * np.pi and np.max(np.abs(np.diff(jumped))) > np.pi
    log = fit_log({"t": t, "q": jumped, "qd": qd, "qdd": qdd, "tau": tau}, cutoff=0).training
    assert np.array_equal(log.data.q, jumped) and log.conventions["unwrapped_jumps"] == 0


def far_off(t):
    """The joint 1e14 turns from zero, as doubles hold it, and its angle reduced independently."""
    q, qd, qdd, tau = joint(t)
    stored = q + 0.5 + 2 * np.pi * 1e14  # doubles here are 0.125 rad apart
    expected = np.unwrap(np.arctan2(np.sin(stored), np.cos(stored)))
    return stored, expected, qd, qdd, tau


def test_far_off_turns_are_removed_from_csv(tmp_path):
    t = np.arange(500) * 0.01
    stored, expected, qd, qdd, tau = far_off(t)
    path = write_csv(tmp_path / "far.csv", "time,position,velocity,acceleration,torque", t, stored, qd, qdd, tau)
    stored = np.loadtxt(path, delimiter=",", skiprows=1)[:, 1]  # what the file holds
    log = load_joint_log(LoadRequest(str(path)))
    np.testing.assert_allclose(log.data.q, expected, rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.cos(log.data.q), np.cos(stored), rtol=0, atol=1e-12)
    assert np.all(np.abs(log.data.q) < 4)
    note = next(note for note in log.notes if "whole turns" in note)
    assert note.startswith(f"{path}: position is 100000000000000 whole turns from zero (about 6.28e+14 rad, where "
                           "doubles are 0.12 rad apart)")
    assert log.conventions["turns_removed"] == 10**14


def test_far_off_turns_are_removed_from_arrays_with_a_convention():
    t = np.arange(500) * 0.01
    stored, expected, qd, qdd, tau = far_off(t)
    fit = fit_log({"t": t, "angle": stored, "qd": qd, "qdd": qdd, "tau": tau}, zero="down", cutoff=0)
    np.testing.assert_allclose(fit.training.data.q, expected - np.pi / 2, rtol=0, atol=1e-9)
    assert fit.training.conventions["turns_removed"] == 10**14
    assert fit.training.conventions["q_from_log"] == "q = angle - pi/2"


def test_ordinary_multi_turn_angles_keep_their_turns():
    t = np.arange(500) * 0.01
    q, qd, qdd, tau = joint(t)
    q = q + 2 * np.pi * 500  # 500 turns: well within float64's precision
    log = fit_log({"t": t, "q": q, "qd": qd, "qdd": qdd, "tau": tau}, cutoff=0).training
    assert np.array_equal(log.data.q, q) and log.conventions["turns_removed"] == 0


# ------------------------------------------------------------------------------------------ the real logs

REAL = "/work/shared/real-logs"
REAL_LOGS = ("pendulum_pd.csv", "pendulum_ddp.csv", "pendulum_energy_shaping.csv")


def real(name):
    import os

    path = os.path.join(REAL, name)
    if not os.path.exists(path):
        pytest.skip(f"{path} is not on this machine")
    return path


@pytest.mark.parametrize("name", REAL_LOGS)
def test_real_logs_give_q_as_position_minus_half_pi(name):
    path = real(name)
    columns = np.loadtxt(path, delimiter=",", skiprows=1)
    time, position, velocity, torque = columns.T
    assert open(path).readline().strip() == "time,position,velocity,torque"
    down = load_joint_log(LoadRequest(path, angle=AngleConvention("down")))
    plain = load_joint_log(LoadRequest(path))
    # Exactly the conversion, sample by sample, and nothing else changed.
    assert np.array_equal(down.data.q, plain.data.q - np.pi / 2)
    for name_ in ("t", "qd", "qdd", "tau"):
        assert np.array_equal(getattr(down.data, name_), getattr(plain.data, name_))
    # The jittered log was resampled (a not-a-knot cubic spline, here scipy's own) before the conversion.
    from scipy.interpolate import CubicSpline

    resampled = CubicSpline(time, position)(down.data.t)
    np.testing.assert_allclose(down.data.q, resampled - np.pi / 2, rtol=0, atol=1e-9)
    np.testing.assert_allclose(G * np.cos(down.data.q), G * np.sin(resampled), rtol=0, atol=1e-8)
    np.testing.assert_allclose(down.data.tau, CubicSpline(time, torque)(down.data.t), rtol=0, atol=1e-9)
    assert down.notes[:2] == (f"{path}: columns read as t=time, q=position, qd=velocity, tau=torque.",
                              f"{path}: angle 0 pointing down, counter-clockwise: q = position - pi/2.")


@pytest.mark.parametrize("name", REAL_LOGS)
def test_real_logs_unresampled_are_exact(name):
    # With an acceleration column nothing is resampled or trimmed: q is the file's position less pi/2, exactly.
    time, position, velocity, torque = np.loadtxt(real(name), delimiter=",", skiprows=1).T
    arrays = {"time": time, "position": position, "velocity": velocity,
              "acceleration": np.gradient(velocity, time), "torque": torque}
    log = fit_log(arrays, zero="down", cutoff=0, sensitivity=False).training
    assert np.array_equal(log.data.q, position - np.pi / 2) and np.array_equal(log.data.tau, torque)
    assert log.conventions["offset_rad"] == -math.pi / 2 and log.conventions["q_from_log"] == "q = position - pi/2"
