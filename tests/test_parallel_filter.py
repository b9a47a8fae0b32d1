"""Parallel filtering: the model's regressor columns and the torque low-passed alike, then decimated; its options."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.signal import butter, sosfiltfilt

from jointid.cli import main
from jointid.csvlog import LogError, LogTable, joint_log_from_table
from jointid.logfit import fit_logs
from jointid.model import model_named
from jointid.parallel_filter import FilterRequest, choose_filter
from jointid.sensitivity import SensitivityCheck, Variant

G = 9.81


def full_log(rate=200.0, duration=10.0, seed=4, coulomb=0.0):
    """t, q, qd, qdd and a noisy tau of the lesson's joint (closed form), uniformly sampled."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(duration * rate) + 1) / rate
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)
    qd = 0.91 * np.cos(1.3 * t) + 0.675 * np.cos(2.7 * t)
    qdd = -1.183 * np.sin(1.3 * t) - 1.8225 * np.sin(2.7 * t)
    tau = 0.8 * qdd + 0.4 * G * np.cos(q) + 0.15 * qd + coulomb * np.sign(qd) + rng.normal(0, 0.3, t.size)
    return {"t": t, "q": q, "qd": qd, "qdd": qdd, "tau": tau}


def table_of(columns, path="log.csv"):
    names = list(columns)
    return LogTable(path, dict(columns), {n: i + 1 for i, n in enumerate(names)}, (), ((0, 0),))


@pytest.mark.parametrize("model", ["plain", "coulomb"])
def test_the_fit_is_least_squares_on_the_filtered_regressor_columns_and_torque(model):
    """Reference: the model's columns built by hand from q, qd, qdd, each filtered by scipy, then every D-th row."""
    data = full_log(coulomb=0.3)
    logs = fit_logs(joint_log_from_table(table_of(data)), model=model_named(model),
                    filtering=FilterRequest(5.0, 10), sensitivity=False)
    columns = [data["qdd"], G * np.cos(data["q"]), data["qd"]] + ([np.sign(data["qd"])] if model == "coulomb" else [])
    sos = butter(4, 5.0, fs=200.0, output="sos")
    X = np.column_stack([sosfiltfilt(sos, c) for c in columns])[::10]
    y = sosfiltfilt(sos, data["tau"])[::10]
    theta = np.linalg.lstsq(X, y, rcond=None)[0]
    np.testing.assert_allclose(logs.result.estimate, theta, rtol=1e-9)
    assert logs.result.training.count == len(y)
    np.testing.assert_allclose(logs.result.training.tau, y, rtol=1e-12)
    # Filtering q and building the columns after would not be the same fit (cos is nonlinear, sign more so).
    q_first = np.column_stack([sosfiltfilt(sos, data["qdd"]), G * np.cos(sosfiltfilt(sos, data["q"])),
                               sosfiltfilt(sos, data["qd"])])[::10]
    if model == "plain":
        assert np.max(np.abs(np.linalg.lstsq(q_first, y, rcond=None)[0] - theta)) > 1e-6


def test_noise_free_data_stay_exact_through_the_filter():
    data = full_log()
    data["tau"] = 0.8 * data["qdd"] + 0.4 * G * np.cos(data["q"]) + 0.15 * data["qd"]
    logs = fit_logs(joint_log_from_table(table_of(data)), filtering=FilterRequest(2.0), sensitivity=False)
    np.testing.assert_allclose(logs.result.estimate, [0.8, 0.4, 0.15], rtol=1e-9)


def test_the_automatic_choice_is_twelve_bandwidths_and_decimates_to_twice_the_cutoff():
    chosen = choose_filter(FilterRequest(), 0.001, True, 0.5, 20_001)
    assert (chosen.cutoff, chosen.decimation) == (6.0, 83)  # 1000 / (2 * 6) rounded down
    assert "automatic: 12 times the motion's bandwidth 0.5 Hz" in chosen.reason
    too_fast = choose_filter(FilterRequest(), 0.1, True, 0.5, 1000)  # 6 Hz against a 5 Hz Nyquist frequency
    assert not too_fast.active and "reaches the Nyquist frequency" in too_fast.reason
    short = choose_filter(FilterRequest(), 0.001, True, 0.5, 1000)
    assert short.decimation == 1000 // 50  # never fewer than 50 samples left


def test_off_and_given_settings(capsys, tmp_path):
    data = full_log()
    path = tmp_path / "log.csv"
    names = list(data)
    path.write_text(",".join(names) + "\n" + "".join(
        ",".join(repr(float(data[n][i])) for n in names) + "\n" for i in range(len(data["t"]))))
    assert main(["fit", "--csv", str(path), "--json", "--cutoff", "0"]) == 0
    off = json.loads(capsys.readouterr().out)
    assert off["low_pass"]["cutoff_hz"] is None and off["samples"] == len(data["t"])
    assert main(["fit", "--csv", str(path), "--json", "--cutoff", "4", "--decimate", "3"]) == 0
    given = json.loads(capsys.readouterr().out)
    assert (given["low_pass"]["cutoff_hz"], given["low_pass"]["decimation"]) == (4.0, 3)
    assert given["samples"] == len(range(0, len(data["t"]), 3))
    cutoffs = [s["cutoff_hz"] for s in given["sensitivity"]["settings"]]
    assert cutoffs == [4.0, 2.0, 8.0]  # nothing differentiated: only the cutoff is varied


@pytest.mark.parametrize("options, words", [
    (["--cutoff", "100"], "cutoff must be below the Nyquist frequency 100 Hz of this log; got 100"),
    (["--cutoff", "-1"], "argument --cutoff: must be a number of hertz, 0 (off) or more"),
    (["--decimate", "0"], "argument --decimate"),
])
def test_filter_mistakes_are_one_line_and_exit_2(capsys, tmp_path, options, words):
    data = full_log(rate=200.0, duration=2.0)
    path = tmp_path / "log.csv"
    path.write_text("t,q,qd,qdd,tau\n" + "".join(
        ",".join(repr(float(data[n][i])) for n in ("t", "q", "qd", "qdd", "tau")) + "\n"
        for i in range(len(data["t"]))))
    try:
        status = main(["fit", "--csv", str(path), *options])
    except SystemExit as stop:
        status = stop.code
    captured = capsys.readouterr()
    assert status == 2 and captured.out == ""
    assert len(captured.err.strip().splitlines()) == 1 and words in captured.err, captured.err


def test_a_jittered_log_with_both_derivatives_is_not_filtered_and_refuses_a_cutoff():
    data = full_log()
    data["t"] = data["t"] + np.random.default_rng(2).uniform(-0.001, 0.001, data["t"].size)
    log = joint_log_from_table(table_of(data))
    logs = fit_logs(log, sensitivity=False)
    assert not logs.filter.active and "not uniform" in logs.filter.reason
    with pytest.raises(LogError, match="cannot be low-passed: the cutoff needs uniformly sampled times"):
        fit_logs(log, filtering=FilterRequest(3.0))


def test_the_sensitivity_flag_is_a_move_of_more_than_two_standard_errors():
    base = Variant("", 1.0, 101, 6.0, np.array([1.0, 2.0, 3.0]))
    variants = (Variant("window", 0.5, 51, 6.0, np.array([1.0, 2.0 + 0.21, 3.0])),
                Variant("cutoff", 2.0, 101, 12.0, np.array([1.0 - 0.19, 2.0, 3.0])))
    check = SensitivityCheck(("I", "h", "B"), base, np.array([0.1, 0.1, 0.1]), variants)
    assert check.flags == (False, True, False)
    assert check.moves[0, 1] == pytest.approx(2.1) and check.moves[1, 0] == pytest.approx(1.9)
    assert check.worst(1)[0].label == "window halved (51 samples)"
    document = check.to_dict()
    assert document["flagged"] is True and document["flags"] == {"I": False, "h": True, "B": False}
    assert [s["setting"] for s in document["settings"]] == [None, "window", "cutoff"]
