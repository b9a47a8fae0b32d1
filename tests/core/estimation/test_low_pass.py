"""Parallel filtering: the model's regressor columns and the torque low-passed alike, then decimated; its options.

The references are independent of jointid: the low-pass is designed here with
scipy.signal (kaiserord, firwin) from its stated specification, applied with
np.convolve at full rate, and every D-th sample with a full window is taken.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.signal import firwin, kaiserord
from support.import_check import packages_loaded

from jointid.cli import main
from jointid.estimation.low_pass import (
    FilterRequest,
    LowPassDesign,
    ParallelFilter,
    choose_filter,
)
from jointid.logs.pipeline import joint_log_from_table
from jointid.logs.table import LogError, LogTable
from jointid.model.terms import model_named
from jointid.present.notes import low_pass_note, low_pass_short_note
from jointid.studies.log_fit import fit_logs
from jointid.studies.sensitivity import SensitivityCheck, Variant

G = 9.81


def reference_taps(cutoff, rate):
    """The stated low-pass, designed by scipy: a Kaiser-windowed sinc for 65 dB over a transition band the cutoff
    wide (narrower near the Nyquist frequency), an odd number of taps, unit gain at 0 Hz."""
    transition = min(cutoff, 2 * (rate / 2 - cutoff))
    count, beta = kaiserord(65.0, transition / (rate / 2))
    return firwin(count | 1, cutoff, window=("kaiser", beta), fs=rate)


def low_passed_rows(column, taps, decimation):
    """np.convolve at full rate, then every decimation-th sample (counted from the first) with a full window."""
    half = (len(taps) - 1) // 2
    full = np.convolve(column, taps, mode="valid")  # full[i] is centred on sample i + half
    rows = [n for n in range(0, len(column), decimation) if half <= n < len(column) - half]
    return full[np.array(rows) - half], rows


def gain(taps, frequencies, rate):
    """The zero-phase gain of symmetric taps: sum_k h[k] cos(2 pi f (k - centre) / rate)."""
    offsets = np.arange(len(taps)) - (len(taps) - 1) / 2
    return np.cos(2 * np.pi * np.outer(frequencies, offsets) / rate) @ taps


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
    """Reference: the model's columns built by hand from q, qd, qdd, each low-passed by np.convolve with scipy's
    taps, then every D-th row with a full window."""
    data = full_log(coulomb=0.3)
    logs = fit_logs(joint_log_from_table(table_of(data)), model=model_named(model),
                    filtering=FilterRequest(5.0, 10), sensitivity=False)
    taps = reference_taps(5.0, 200.0)
    columns = [data["qdd"], G * np.cos(data["q"]), data["qd"]] + ([np.sign(data["qd"])] if model == "coulomb" else [])
    X = np.column_stack([low_passed_rows(c, taps, 10)[0] for c in columns])
    y, rows = low_passed_rows(data["tau"], taps, 10)
    theta = np.linalg.lstsq(X, y, rcond=None)[0]
    np.testing.assert_allclose(logs.result.estimate, theta, rtol=1e-9)
    assert logs.result.training.count == len(y)
    np.testing.assert_allclose(logs.result.training.tau, y, rtol=1e-12)
    np.testing.assert_array_equal(logs.result.training.t, data["t"][rows])  # the kept instants, not shifted
    # Filtering q and building the columns after would not be the same fit (cos is nonlinear, sign more so).
    q_first = np.column_stack([low_passed_rows(data["qdd"], taps, 10)[0],
                               G * np.cos(low_passed_rows(data["q"], taps, 10)[0]),
                               low_passed_rows(data["qd"], taps, 10)[0]])
    if model == "plain":
        assert np.max(np.abs(np.linalg.lstsq(q_first, y, rcond=None)[0] - theta)) > 1e-6


@pytest.mark.parametrize("rate", [50.0, 200.0, 1000.0])
def test_the_taps_are_the_stated_low_pass(rate):
    """Flat within 0.1 % to half the cutoff, 60 dB down from 1.5 times it (or the narrower band near Nyquist),
    half the amplitude at the cutoff, unit gain at 0 Hz, symmetric (zero phase): read from the taps."""
    for cutoff in np.geomspace(rate / 400, 0.49 * rate, 9):
        taps = LowPassDesign(cutoff, rate).taps
        np.testing.assert_allclose(taps, reference_taps(cutoff, rate), rtol=0, atol=1e-15)
        assert len(taps) % 2 == 1 and np.array_equal(taps, taps[::-1]) and taps.sum() == pytest.approx(1, abs=1e-14)
        transition = min(cutoff, 2 * (rate / 2 - cutoff))
        frequencies = np.linspace(0, rate / 2, 4001)
        response = gain(taps, frequencies, rate)
        passband = frequencies <= cutoff - transition / 2
        stopband = frequencies >= cutoff + transition / 2
        assert np.max(np.abs(response[passband] - 1)) <= 1e-3, cutoff
        assert np.max(np.abs(response[stopband])) <= 1e-3, cutoff
        assert gain(taps, [cutoff], rate)[0] == pytest.approx(0.5, abs=2e-3)


def test_only_the_kept_samples_are_computed_and_they_are_the_full_rate_filter_s():
    """Polyphase at the kept rows against np.convolve at full rate, over random lengths, rates and decimations."""
    rng = np.random.default_rng(11)
    for _ in range(60):
        rate = float(rng.choice([50, 300, 1000]))
        cutoff = float(rng.uniform(0.02, 0.45)) * rate
        decimation = int(rng.integers(1, 40))
        chosen = ParallelFilter(cutoff, rate, decimation, "test")
        taps = reference_taps(cutoff, rate)
        count = int(rng.integers(len(taps), len(taps) + 2000))
        columns = rng.normal(size=(count, 2))
        expected, rows = low_passed_rows(columns[:, 1], taps, decimation)
        np.testing.assert_array_equal(chosen.rows(count), rows)
        np.testing.assert_allclose(chosen.apply(columns)[:, 1], expected, rtol=0, atol=1e-13)
        np.testing.assert_allclose(chosen.apply_column(np.ascontiguousarray(columns[:, 1])), expected,
                                   rtol=0, atol=1e-13)


def test_one_filter_on_both_sides_keeps_the_model_exact():
    """L(X theta) = L(X) theta for hand-built columns, including a sign column and a constant."""
    rng = np.random.default_rng(2)
    t = np.arange(5000) / 500.0
    q = 0.9 * np.sin(0.7 * t) + 0.3 * np.sin(2.9 * t + 1)
    X = np.column_stack([np.gradient(np.gradient(q, t), t), G * np.cos(q), np.gradient(q, t),
                         np.sign(np.gradient(q, t)), np.ones_like(t)])
    theta = rng.normal(size=5)
    chosen = ParallelFilter(4.0, 500.0, 62, "test")
    np.testing.assert_allclose(chosen.apply_column(X @ theta), chosen.apply(X) @ theta, rtol=0, atol=1e-12)
    np.testing.assert_allclose(chosen.apply(X)[:, 4], 1.0, rtol=0, atol=1e-14)  # unit gain at 0 Hz


def test_a_default_log_fit_imports_no_scipy(tmp_path):
    data = full_log()
    path = tmp_path / "log.csv"
    path.write_text("t,q,tau\n" + "".join(f"{a!r},{b!r},{c!r}\n" for a, b, c in
                                          zip(data["t"], data["q"], data["tau"])))
    run = f"jointid.cli.main(['fit', '--csv', {str(path)!r}, '--json'])"
    assert packages_loaded("jointid.cli", {"scipy"}, run) == []


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
    with_window = 1000 - (len(reference_taps(6.0, 1000.0)) - 1)  # samples with a full window of taps
    assert short.decimation == with_window // 50  # never fewer than 50 samples left
    assert len(short.rows(1000)) >= 50
    shorter = choose_filter(FilterRequest(), 0.001, True, 0.5, 600)  # fewer samples than taps + 50
    assert not shorter.active and "leaves fewer than 50 of the log's 600 samples with a full window" in shorter.reason


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
    low_pass = given["low_pass"]
    assert (low_pass["cutoff_hz"], low_pass["decimation"]) == (4.0, 3)
    taps = len(reference_taps(4.0, 200.0))
    assert (low_pass["taps"], low_pass["edge_samples_dropped"]) == (taps, (taps - 1) // 2)
    assert (low_pass["passband_edge_hz"], low_pass["stopband_edge_hz"]) == (2.0, 6.0)
    assert given["samples"] == len(low_passed_rows(data["t"], np.ones(taps) / taps, 3)[1])
    cutoffs = [s["cutoff_hz"] for s in given["sensitivity"]["settings"]]
    assert cutoffs == [4.0, 2.0, 8.0]  # nothing differentiated: only the cutoff is varied


@pytest.mark.parametrize("options, words", [
    (["--cutoff", "100"], "cutoff must be below the Nyquist frequency 100 Hz of this log; got 100"),
    (["--cutoff", "-1"], "argument --cutoff: must be a number of hertz, 0 (off) or more"),
    (["--decimate", "0"], "argument --decimate"),
    (["--cutoff", "0.5"], "cannot be low-passed: the cutoff 0.5 Hz needs at least"),
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


def test_an_exact_fit_flags_nothing_however_many_rounding_errors_its_moves_are():
    base = Variant("", 1.0, None, 6.0, np.array([0.8, 0.4, 0.15]))
    variants = (Variant("cutoff", 0.5, None, 3.0, np.array([0.8 + 2e-16, 0.4, 0.15 - 3e-17])),)
    std_error = np.array([1e-17, 1e-18, 1e-17])
    judged = SensitivityCheck(("I", "h", "B"), base, std_error, variants)
    assert judged.flags == (True, False, True)  # 20 and 3 "standard errors" of rounding
    exact = SensitivityCheck(("I", "h", "B"), base, std_error, variants, exact=True)
    assert exact.flags == (False, False, False) and not exact.flagged
    assert exact.relative_moves == pytest.approx([2e-16 / 0.8, 0.0, 3e-17 / 0.15])
    document = exact.to_dict()
    assert document["exact_fit"] is True and set(document["largest_move_std_errors"].values()) == {None}


@pytest.mark.parametrize("noise", [0.0, 1e-6])
def test_noise_free_torques_make_an_exact_fit_and_any_noise_a_judged_one(noise, tmp_path, capsys):
    """A log of the closed-form joint with its true derivatives: without noise the low-passed fit reproduces the
    torques to rounding, so the check says so instead of flagging moves of 1e-16 as many standard errors."""
    data = full_log()
    rng = np.random.default_rng(9)
    data["tau"] = (0.8 * data["qdd"] + 0.4 * G * np.cos(data["q"]) + 0.15 * data["qd"]
                   + noise * rng.standard_normal(data["t"].size))
    path = tmp_path / "log.csv"
    np.savetxt(path, np.column_stack(list(data.values())), delimiter=",", header="t,q,qd,qdd,tau", comments="",
               fmt="%.17g")
    assert main(["fit", "--csv", str(path), "--json"]) == 0
    check = json.loads(capsys.readouterr().out)["sensitivity"]
    assert check["exact_fit"] is (noise == 0.0)
    assert check["flagged"] is False
    if noise == 0.0:
        assert max(check["largest_relative_move"].values()) < 1e-12
        assert main(["fit", "--csv", str(path)]) == 0
        text = capsys.readouterr().out
        assert "fitted exactly (noise-free data)" in text and "decide this estimate" not in text
    else:
        assert all(move is not None for move in check["largest_move_std_errors"].values())


def test_the_note_names_the_filter_and_counts_in_ordinals():
    chosen = ParallelFilter(5.0, 200.0, 21, "cutoff given")
    taps = len(reference_taps(5.0, 200.0))
    assert low_pass_note(chosen) == (
        f"torque and every regressor column low-passed alike at 5 Hz (zero-phase FIR, Kaiser-windowed sinc, "
        f"{taps} taps, Kaiser beta 6.2: flat within 0.1% below 2.5 Hz, 60 dB down above 7.5 Hz; the "
        f"{(taps - 1) // 2} samples at each end, without a full window, not kept), then every 21st sample kept "
        f"(cutoff given); the training RMSE is of the filtered torque.")
    assert low_pass_short_note(chosen) == "torque and regressor low-passed at 5 Hz, every 21st sample kept"
    assert ", every 22nd sample" in low_pass_short_note(ParallelFilter(5.0, 200.0, 22, ""))
    assert ", every 12th sample" in low_pass_short_note(ParallelFilter(5.0, 200.0, 12, ""))
