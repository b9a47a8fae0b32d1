"""--train-window, --heldout-window and --effort-scale on CSV logs: the same cuts and scale as for bags."""

from __future__ import annotations

import json
import math

import numpy as np

from jointid.cli import main

TRUE = {"I": 0.8, "h": 0.4, "B": 0.15}


def write_log(path, t, noise_seed=5):
    """A CSV log of q = 0.7 sin(1.3 t) + 0.25 sin(2.7 t) with its exact derivatives and a noisy torque."""
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)
    qd = 0.7 * 1.3 * np.cos(1.3 * t) + 0.25 * 2.7 * np.cos(2.7 * t)
    qdd = -0.7 * 1.3**2 * np.sin(1.3 * t) - 0.25 * 2.7**2 * np.sin(2.7 * t)
    tau = TRUE["I"] * qdd + TRUE["h"] * 9.81 * np.cos(q) + TRUE["B"] * qd
    tau += np.random.default_rng(noise_seed).uniform(-0.05, 0.05, len(t))
    rows = np.column_stack([t, q, qd, qdd, tau])
    np.savetxt(path, rows, delimiter=",", header="t,q,qd,qdd,tau", comments="", fmt="%.17g")
    return rows


def fit(capsys, *argv) -> dict:
    assert main(["fit", *argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_windows_of_one_csv_log_equal_separate_logs(tmp_path, capsys):
    t = np.arange(4001) / 250.0  # 16 s at 250 Hz
    rows = write_log(tmp_path / "all.csv", t)
    early, late = rows[t <= 6.0], rows[(t >= 10.0) & (t <= 16.0)]
    header = "t,q,qd,qdd,tau"
    np.savetxt(tmp_path / "early.csv", early, delimiter=",", header=header, comments="", fmt="%.17g")
    np.savetxt(tmp_path / "late.csv", late, delimiter=",", header=header, comments="", fmt="%.17g")
    windowed = fit(capsys, "--csv", str(tmp_path / "all.csv"), "--train-window", ":6", "--heldout-window", "10:")
    separate = fit(capsys, "--csv", str(tmp_path / "early.csv"), "--heldout", str(tmp_path / "late.csv"))
    assert windowed["estimate"] == separate["estimate"]
    assert windowed["heldout_rmse"] == separate["heldout_rmse"]
    assert windowed["samples"] == separate["samples"]
    assert any("training window 0:6 s from the log's start: 1501 of 4001" in n
               for n in windowed["notes"])
    assert any("held-out window 10: s from the log's start: 1501 of 4001" in n for n in windowed["notes"])
    assert windowed["logs"] == {
        "training": {"path": str(tmp_path / "all.csv"), "format": "csv",
                     "time_window": {"start_s": 0.0, "end_s": 6.0}, "effort_scale": 1.0},
        "heldout": {"path": str(tmp_path / "all.csv"), "format": "csv",
                    "time_window": {"start_s": 10.0, "end_s": None}, "effort_scale": 1.0}}
    assert separate["logs"]["heldout"]["time_window"] is None


def test_errors_inside_a_window_name_the_files_line(tmp_path, capsys):
    t = np.arange(1000) / 100.0
    write_log(tmp_path / "log.csv", t)
    lines = (tmp_path / "log.csv").read_text().splitlines()
    lines[801] = lines[801].replace(lines[801].split(",")[1], "nan", 1)  # data row 800 is line 802
    (tmp_path / "log.csv").write_text("\n".join(lines) + "\n")
    # The reader refuses the NaN before any cut, at its line in the file.
    assert main(["fit", "--csv", str(tmp_path / "log.csv"), "--train-window", "5:9"]) == 2
    assert "row 802, column 2 (q): NaN is not a measurement" in capsys.readouterr().err


def test_effort_scale_multiplies_the_torque_of_a_csv_log(tmp_path, capsys):
    t = np.arange(2001) / 250.0
    write_log(tmp_path / "log.csv", t)
    plain = fit(capsys, "--csv", str(tmp_path / "log.csv"))
    scaled = fit(capsys, "--csv", str(tmp_path / "log.csv"), "--effort-scale", "-0.5")
    for name in TRUE:
        assert math.isclose(scaled["estimate"][name], -0.5 * plain["estimate"][name], rel_tol=1e-9)
    assert any("torque = -0.5 × tau, in N m (--effort-scale -0.5)" in n for n in scaled["notes"])
    assert not any("effort-scale" in n for n in plain["notes"])
    assert scaled["logs"]["training"]["effort_scale"] == -0.5 and plain["logs"]["training"]["effort_scale"] == 1.0
