"""Several runs of one joint: the runs already fitted are pooled as they are, one more run is added to them
without refitting them, and a log whose angle is read in a unit its column does not name is refused."""

from __future__ import annotations

import re

import numpy as np
import pytest

from jointid.logs.conventions import ColumnMap
from jointid.logs.request import LoadRequest, load_joint_log
from jointid.logs.table import LogError
from jointid.model.terms import model_named
from jointid.studies.runs import add_run, fit_runs

G = 9.81
TRUTH = {"I": 0.8, "h": 0.4, "B": 0.15}


def write_run(path, seed: int, angle: str = "q", scale: float = 1.0):
    """A plain joint swinging on a two-sine motion, 12 s at 200 Hz, torque noise 0.02 N m; the angle column
    named `angle` and given in its unit (`scale` per radian)."""
    rng = np.random.default_rng(seed)
    t = np.arange(0, 12, 1 / 200)
    a, w = 0.6 + 0.1 * seed, 1.1 + 0.2 * seed
    q = a * np.sin(w * t) + 0.2 * np.sin(2.9 * t)
    qd = a * w * np.cos(w * t) + 0.58 * np.cos(2.9 * t)
    qdd = -a * w * w * np.sin(w * t) - 0.2 * 2.9**2 * np.sin(2.9 * t)
    tau = TRUTH["I"] * qdd + TRUTH["h"] * G * np.cos(q) + TRUTH["B"] * qd + 0.02 * rng.standard_normal(len(t))
    lines = [f"t,{angle},tau"] + [f"{a:.6f},{b * scale:.9f},{c:.9f}" for a, b, c in zip(t, q, tau)]
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def test_a_run_added_to_pooled_runs_is_the_pooled_fit_of_all_three_and_keeps_the_first_two_as_fitted(tmp_path):
    paths = [write_run(tmp_path / f"run{k}.csv", k) for k in range(3)]
    logs = [load_joint_log(LoadRequest(path)) for path in paths]
    plain = model_named("plain")
    two = fit_runs(logs[:2], plain, sensitivity=False)
    three = add_run(two, logs[2], plain, sensitivity=False)
    assert three.runs[:2] == two.runs  # the same fits, not refitted
    everyone = fit_runs(logs, plain, sensitivity=False)
    for name, true in TRUTH.items():
        assert three.params[name] == pytest.approx(everyone.params[name], rel=1e-12)
        assert abs(three.params[name] - true) <= max(0.02 * true, 3 * three.bse[name]), name


def test_a_log_whose_angle_column_names_degrees_but_is_read_in_radians_is_refused(tmp_path):
    """Read as radians, a log in degrees fits a joint 57 times too small, and its runs would not pool with
    others: refused in one line; read in its unit, it pools with a run in radians and gives the joint."""
    radians = write_run(tmp_path / "a.csv", 0, "angle_rad")
    degrees = write_run(tmp_path / "b.csv", 1, "angle_deg", 180 / np.pi)
    with pytest.raises(LogError) as refused:
        load_joint_log(LoadRequest(degrees, columns=ColumnMap.parse("q=angle_deg")))
    message = str(refused.value)
    assert "b.csv" in message and "'angle_deg' in degrees but it is read in radians: give --degrees" in message
    assert "\n" not in message
    with pytest.raises(LogError, match="'angle_rad' in radians but it is read in degrees: drop --degrees"):
        load_joint_log(LoadRequest(radians, degrees=True, columns=ColumnMap.parse("q=angle_rad")))
    logs = [load_joint_log(LoadRequest(radians, columns=ColumnMap.parse("q=angle_rad"))),
            load_joint_log(LoadRequest(degrees, degrees=True, columns=ColumnMap.parse("q=angle_deg")))]
    pooled = fit_runs(logs, model_named("plain"), sensitivity=False)
    for name, true in TRUTH.items():
        assert abs(pooled.params[name] - true) <= max(0.02 * true, 3 * pooled.bse[name]), name


def test_a_sysid_routines_pooled_gains_are_judged_by_their_pooled_refits(capsys):
    """A SysId routine's tests do not stand alone, so their pooled gains are judged by the pooled fit redone from
    every test's derivative window halved and doubled and without the robust step: a move beyond two noise errors
    of the difference widens the gain's error by what noise leaves of it, and the verdict follows the widened error
    in the runs' JSON and in the gains (a gain moved by 1 % stays well determined however many errors that is)."""
    import json
    import math
    from pathlib import Path

    import jointid
    from jointid.cli import main
    from jointid.estimation.uncertainty import verdict
    from jointid.studies.log_fit import LoadedLogs, refits_of
    from jointid.studies.runs import pool_runs

    path = Path(__file__).resolve().parents[3] / "docs" / "examples" / "sysid_arm.wpilog"
    pooled = jointid.fit_wpilog(str(path))
    refits = [refits_of(run) for run in pooled.runs]
    extra = {name: 0.0 for name in pooled.shared}
    robust = {name: 0.0 for name in pooled.shared}  # a choice of its own, added in quadrature to the window's
    for label in ("window halved", "window doubled", "--no-robust"):
        redone = tuple(LoadedLogs(run.training, None, found[label]) for run, found in zip(pooled.runs, refits))
        again = pool_runs(redone, pooled.weighting)
        for name in pooled.shared:
            noise, other = pooled.noise_bse[name], again.noise_bse[name]
            allowed = max(noise**2, abs(other**2 - noise**2))  # the two pooled fits' difference from noise alone
            move = abs(again.params[name] - pooled.params[name])
            if move > 2 * math.sqrt(allowed):
                found = robust if label == "--no-robust" else extra
                found[name] = max(found[name], math.sqrt(move**2 - allowed))
    extra = {name: math.hypot(extra[name], robust[name]) for name in pooled.shared}
    assert main(["fit", "--wpilog", str(path), "--gains", "wpilib", "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    gains = document["gains"]["gains"]
    for name in pooled.shared:
        widened = math.hypot(pooled.noise_bse[name], extra[name])
        assert document["pooled"]["std_error"][name] == pytest.approx(widened, rel=1e-9)
        assert document["pooled"]["noise_std_error"][name] == pytest.approx(pooled.noise_bse[name], rel=1e-12)
        expected = verdict(100 * widened / abs(pooled.params[name]))
        assert document["pooled"]["verdicts"][name] == expected
        if extra[name] > 0:
            assert document["pooled"]["verdict_reasons"][name].startswith("error widened from ")
        if name in gains:
            assert gains[name]["verdict"] == expected
    assert any(extra[name] > 0 for name in ("kA", "kG", "kV", "kS"))  # the case the rule is for occurs here
    # The gains the refits move by a few percent at most stay well determined: no over-caution.
    assert document["pooled"]["verdicts"]["kV"] == "well determined"
