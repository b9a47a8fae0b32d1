"""Command line for logs as robots write them: --columns, --zero, --clockwise, the notes and JSON, the refusals.

Every refusal is one line on stderr and exit status 2, without a traceback; expected estimates come from
numpy.linalg.lstsq on the closed-form joint's true columns.
"""

import json
import math
import os

import numpy as np
import pytest
from support.cli_support import fit_json, refused, run
from support.conventions_support import TRUE, joint, logged, lstsq

from jointid.cli import main

REAL = "/work/shared/real-logs"
REAL_LOGS = ("pendulum_pd.csv", "pendulum_ddp.csv", "pendulum_energy_shaping.csv")


def write_csv(path, header, *columns):
    np.savetxt(path, np.column_stack(columns), delimiter=",", header=header, comments="", fmt="%.17g")
    return path


def estimate(document):
    return np.array([document["estimate"][name] for name in ("I", "h", "B")])


@pytest.fixture
def robot_log(tmp_path):
    """A log as a robot writes it: time, position (0 hanging down, clockwise), velocity, acceleration, effort."""
    t = np.arange(1500) * 0.004
    a, ad, add, tau_a = logged(t, "down", clockwise=True)
    return write_csv(tmp_path / "robot.csv", "time,position,velocity,acceleration,effort", t, a, ad, add, tau_a), t


def test_zero_and_clockwise_on_the_command_line(capsys, robot_log):
    path, t = robot_log
    q, qd, qdd, tau = joint(t)
    document = fit_json(capsys, "--csv", path, "--zero", "down", "--clockwise", "--cutoff", "0")
    np.testing.assert_allclose(estimate(document), lstsq(q, qd, qdd, tau), rtol=1e-8)
    assert document["notes"][:2] == [
        f"{path}: columns read as t=time, q=position, qd=velocity, qdd=acceleration, tau=effort.",
        f"{path}: angle 0 pointing down, clockwise: q = -pi/2 - position, and qd, qdd and tau change sign (a torque "
        "the log calls positive turns toward increasing logged angle, which is decreasing q)."]
    assert document["conventions"] == {"training": {
        "columns": {"t": "time", "q": "position", "qd": "velocity", "qdd": "acceleration", "tau": "effort"},
        "zero": "down", "clockwise": True, "sign": -1, "offset_rad": -math.pi / 2,
        "q_from_log": "q = -pi/2 - position", "unwrapped_jumps": 0, "wrapped_range": None, "turns_removed": 0},
        "heldout": None}
    # The text output carries the same notes.
    status, out, _ = run(capsys, "fit", "--csv", path, "--zero", "down", "--clockwise", "--cutoff", "0")
    assert status == 0 and "Note: " + document["notes"][1] in out


def test_columns_flag_maps_names(capsys, tmp_path):
    t = np.arange(800) * 0.005
    q, qd, qdd, tau = joint(t)
    path = write_csv(tmp_path / "odd.csv", "stamp,posn,rate,acc,trq", t, q, qd, qdd, tau)
    document = fit_json(capsys, "--csv", path, "--columns", "t=stamp,q=posn,qd=rate,qdd=acc,tau=trq", "--cutoff", "0")
    np.testing.assert_allclose(estimate(document), TRUE, rtol=1e-8)
    assert document["notes"][0] == f"{path}: columns read as t=stamp, q=posn, qd=rate, qdd=acc, tau=trq."
    # The held-out log is read with the same map.
    document = fit_json(capsys, "--csv", path, "--heldout", path, "--columns", "t=stamp,q=posn,qd=rate,qdd=acc,tau=trq",
                        "--cutoff", "0")
    assert document["heldout_rmse"] < 1e-9 and document["conventions"]["heldout"]["columns"]["q"] == "posn"


@pytest.mark.parametrize("name", REAL_LOGS)
def test_real_logs_load_with_zero_down(capsys, name):
    path = os.path.join(REAL, name)
    if not os.path.exists(path):
        pytest.skip(f"{path} is not on this machine")
    document = fit_json(capsys, "--csv", path, "--zero", "down", "--model", "coulomb+bias")
    assert document["notes"][:2] == [f"{path}: columns read as t=time, q=position, qd=velocity, tau=torque.",
                                     f"{path}: angle 0 pointing down, counter-clockwise: q = position - pi/2."]
    conventions = document["conventions"]["training"]
    assert conventions["columns"] == {"t": "time", "q": "position", "qd": "velocity", "tau": "torque"}
    assert conventions["offset_rad"] == -math.pi / 2 and conventions["q_from_log"] == "q = position - pi/2"
    if name == "pendulum_energy_shaping.csv":
        return  # hand pushes the log does not record: its fit is a matter for a robust fit, not for the reading
    # The README's hardware: h = m l_com about 0.30-0.34 kg m (0.3377 held still at five angles); read with the
    # zero pointing right instead, gravity's column is a quarter turn off and h all but vanishes.
    wrong = fit_json(capsys, "--csv", path, "--model", "coulomb+bias")
    assert 0.25 < document["estimate"]["h"] < 0.5 and abs(wrong["estimate"]["h"]) < 0.1
    assert document["training_rmse"] < wrong["training_rmse"]


@pytest.mark.parametrize("argv, line", [
    (["--columns", "pos=position"], "jointid fit: argument --columns: unknown quantity 'pos' in pos=position; the "
                                    "quantities are t, q, qd, qdd, tau"),
    (["--columns", "q"], "jointid fit: argument --columns: 'q' is not QUANTITY=NAME; give e.g. "
                         "t=time,q=position,tau=effort"),
    (["--columns", "q=position,qd=position"], "jointid fit: argument --columns: column 'position' is given for both "
                                              "q and qd"),
    (["--zero", "below"], "jointid fit: argument --zero: invalid choice: 'below' (choose from 'right', 'up', 'left', "
                          "'down')"),
])
def test_bad_flags_are_one_line(capsys, robot_log, argv, line):
    path, _ = robot_log
    assert refused(capsys, "fit", "--csv", path, *argv) == line


def test_a_map_naming_a_missing_column_is_one_line(capsys, robot_log):
    path, _ = robot_log
    assert refused(capsys, "fit", "--csv", path, "--columns", "q=posn") == (
        f"jointid: {path}, row 1: --columns q=posn: the log has no column 'posn'; its columns are time, position, "
        "velocity, acceleration, effort")


def test_runs_whose_angle_column_names_degrees_are_refused_unless_read_in_degrees(capsys, tmp_path):
    """Read as radians, a log in degrees fits a joint 57 times too small: one line and status 2, naming the fix."""
    t = np.arange(0, 8, 0.005)
    q = 0.6 * np.sin(1.3 * t)
    tau = 0.8 * -0.6 * 1.69 * np.sin(1.3 * t) + 0.4 * 9.81 * np.cos(q)
    paths = []
    for k in (1, 2):
        path = tmp_path / f"run{k}.csv"
        path.write_text("time,position_deg,torque\n" + "".join(
            f"{a:.4f},{math.degrees(b):.9f},{c:.9f}\n" for a, b, c in zip(t, q, tau)))
        paths += ["--csv", str(path)]
    line = refused(capsys, "fit", "--columns", "q=position_deg", "--model", "plain", *paths)
    assert line == (f"jointid: {tmp_path / 'run1.csv'}: names its angle column 'position_deg' in degrees but it is "
                    "read in radians: give --degrees (it applies to every log read; convert a log whose unit "
                    "differs)")
    assert main(["fit", "--columns", "q=position_deg", "--degrees", "--model", "plain", "--json", *paths]) == 0
    pooled = json.loads(capsys.readouterr().out)["pooled"]["estimate"]
    assert pooled["I"] == pytest.approx(0.8, rel=0.02) and pooled["h"] == pytest.approx(0.4, rel=0.02)


def test_two_columns_for_one_quantity_are_one_line(capsys, tmp_path):
    path = tmp_path / "both.csv"
    path.write_text("time,q,position,torque\n0,0,0,1\n0.01,0,0,1\n0.02,0,0,1\n0.03,0,0,1\n")
    assert refused(capsys, "fit", "--csv", path) == (
        f"jointid: {path}, row 1: columns 2 ('q') and 3 ('position') both give q; keep one, or choose one with "
        "--columns q=NAME")


def test_flags_need_a_log_and_columns_need_a_csv(capsys):
    assert refused(capsys, "fit", "--zero", "down") == (
        "jointid: --zero: only for fitting a log; add --csv TRAIN.csv, --bag BAG --joint NAME or --wpilog LOG.wpilog")
    assert refused(capsys, "fit", "--columns", "q=a") == (
        "jointid: --columns: only for fitting a log; add --csv TRAIN.csv, --bag BAG --joint NAME "
        "or --wpilog LOG.wpilog")
    assert refused(capsys, "fit", "--bag", "x.bag", "--joint", "j", "--columns", "q=a") == (
        "jointid: --columns: only for a CSV log; a bag's JointState gives position, velocity and effort by name")


def test_plain_logs_are_read_as_before(capsys, tmp_path):
    t = np.arange(600) * 0.005
    q, qd, qdd, tau = joint(t)
    path = write_csv(tmp_path / "plain.csv", "t,q,qd,qdd,tau", t, q, qd, qdd, tau)
    document = fit_json(capsys, "--csv", path, "--cutoff", "0")
    assert not any("columns read as" in note or "angle 0" in note or "wrapped" in note for note in document["notes"])
    assert document["conventions"]["training"]["zero"] == "right"
    assert document["conventions"]["training"]["q_from_log"] == "q = logged q"


def test_a_log_read_without_its_zero_is_pointed_to_zero(capsys, tmp_path):
    """A log whose angle 0 hangs down, read as if it were horizontal: cos q of the logged angle is -sin q of
    jointid's, so the residuals follow an angle offset, and the text names --zero as well as the model."""
    t = np.arange(1500) * 0.004
    a, ad, add, tau_a = logged(t, "down", clockwise=False)
    path = write_csv(tmp_path / "down.csv", "time,position,velocity,acceleration,effort", t, a, ad, add, tau_a)
    status, out, err = run(capsys, "fit", "--csv", path, "--model", "plain")
    assert status == 0, err
    sentence = next(line for line in out.splitlines() if line.startswith("The residuals follow"))
    assert "an angle offset" in sentence and "--zero down, up or left" in sentence
    status, out, err = run(capsys, "fit", "--csv", path, "--model", "plain", "--zero", "down")
    assert status == 0 and "--zero down, up or left" not in out
