"""Parallel filtering: the model's regressor columns and the torque low-passed alike, then decimated; its options.

The references are independent of jointid: the low-pass is designed here with
scipy.signal (kaiserord, firwin) from its stated specification, each column is
extended past its ends by its odd reflection about a line fitted (np.polyfit) to
its last half cutoff period, filtered with np.convolve at full rate, and every
D-th sample is taken.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.signal import firwin, kaiserord
from support.import_check import packages_loaded

from jointid.cli import main
from jointid.estimation import low_pass
from jointid.estimation.low_pass import (
    FilterRequest,
    LowPassDesign,
    ParallelFilter,
    choose_filter,
    low_passed_together,
    noise_cap,
    shared_size,
)
from jointid.logs.pipeline import joint_log_from_table
from jointid.logs.table import LogError, LogTable
from jointid.model.terms import model_named
from jointid.present.notes import low_pass_note, low_pass_short_note
from jointid.estimation.exclusion import ExclusionRequest
from jointid.studies.log_fit import fit_logs
from jointid.studies.sensitivity import SensitivityCheck, Variant

G = 9.81


def reference_taps(cutoff, rate):
    """The stated low-pass, designed by scipy: a Kaiser-windowed sinc for 65 dB over a transition band the cutoff
    wide (narrower near the Nyquist frequency), an odd number of taps, unit gain at 0 Hz."""
    transition = min(cutoff, 2 * (rate / 2 - cutoff))
    count, beta = kaiserord(65.0, transition / (rate / 2))
    return firwin(count | 1, cutoff, window=("kaiser", beta), fs=rate)


def extended(column, count, fitted):
    """The column continued `count` samples past each end by its odd reflection about the straight line fitted to
    its first (last) `fitted` samples; held at the reflection's last value beyond one reflection."""
    n = len(column)
    fitted = min(fitted, n)
    start = np.polyval(np.polyfit(np.arange(fitted), column[:fitted], 1), 0)
    end = np.polyval(np.polyfit(np.arange(fitted), column[n - fitted:], 1), fitted - 1)
    reach = min(count, n - 1)
    left = 2 * start - column[1:reach + 1][::-1]
    right = 2 * end - column[n - 1 - reach:n - 1][::-1]
    return np.concatenate([np.full(count - reach, left[0]), left, column, right, np.full(count - reach, right[-1])])


def low_passed_rows(column, taps, decimation, rate, cutoff):
    """The extended column through np.convolve at full rate, then every decimation-th sample from the first."""
    half = (len(taps) - 1) // 2
    full = np.convolve(extended(column, half, max(3, round(0.5 * rate / cutoff))), taps, mode="valid")
    rows = list(range(0, len(column), decimation))
    return full[rows], rows


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


@pytest.mark.parametrize("model", ["plain", "bias"])
def test_the_fit_is_least_squares_on_the_filtered_regressor_columns_and_torque(model):
    """Reference: the model's columns built by hand from q, qd, qdd, each low-passed by np.convolve with scipy's
    taps after the stated extension, then every D-th row (every sample kept: --no-robust, no Coulomb term)."""
    data = full_log(coulomb=0.3)
    logs = fit_logs(joint_log_from_table(table_of(data)), model=model_named(model),
                    filtering=FilterRequest(5.0, 10), sensitivity=False, exclusion=ExclusionRequest(robust=False))
    taps = reference_taps(5.0, 200.0)
    columns = [data["qdd"], G * np.cos(data["q"]), data["qd"]] + ([np.ones_like(data["q"])] if model == "bias" else [])
    X = np.column_stack([low_passed_rows(c, taps, 10, 200.0, 5.0)[0] for c in columns])
    y, rows = low_passed_rows(data["tau"], taps, 10, 200.0, 5.0)
    theta = np.linalg.lstsq(X, y, rcond=None)[0]
    np.testing.assert_allclose(logs.result.estimate, theta, rtol=1e-9)
    assert logs.result.training.count == len(y)
    np.testing.assert_allclose(logs.result.training.tau, y, rtol=1e-12)
    np.testing.assert_array_equal(logs.result.training.t, data["t"][rows])  # the kept instants, not shifted
    # Filtering q and building the columns after would not be the same fit (cos is nonlinear, sign more so).
    q_first = np.column_stack([low_passed_rows(data["qdd"], taps, 10, 200.0, 5.0)[0],
                               G * np.cos(low_passed_rows(data["q"], taps, 10, 200.0, 5.0)[0]),
                               low_passed_rows(data["qd"], taps, 10, 200.0, 5.0)[0]])
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


@pytest.mark.parametrize("fft_cost", [0.0, 3.6, np.inf], ids=["fft", "cheaper", "polyphase"])
def test_only_the_kept_samples_are_computed_and_they_are_the_full_rate_filter_s(fft_cost, monkeypatch):
    """Polyphase or FFT blocks at the kept rows against np.convolve at full rate, over random lengths, rates and
    decimations."""
    monkeypatch.setattr(low_pass, "FFT_COST", fft_cost)
    rng = np.random.default_rng(11)
    for _ in range(60):
        rate = float(rng.choice([50, 300, 1000]))
        cutoff = float(rng.uniform(0.02, 0.45)) * rate
        decimation = int(rng.integers(1, 40))
        chosen = ParallelFilter(cutoff, rate, decimation, "test")
        taps = reference_taps(cutoff, rate)
        count = int(rng.integers(len(taps) // 2 + 2, len(taps) + 2000))
        columns = rng.normal(size=(count, 2))
        expected, rows = low_passed_rows(columns[:, 1], taps, decimation, rate, cutoff)
        np.testing.assert_array_equal(chosen.rows(count), rows)
        np.testing.assert_allclose(chosen.apply(columns)[:, 1], expected, rtol=0, atol=1e-13)
        np.testing.assert_allclose(chosen.apply_column(np.ascontiguousarray(columns[:, 1])), expected,
                                   rtol=0, atol=1e-13)


def test_filters_sharing_one_spectrum_give_each_filter_s_full_rate_outputs(monkeypatch):
    """A cutoff and its half and double from one spectrum per block against np.convolve at full rate, over random
    lengths (down to just over the longest filter's half), rates and decimations (odd and even block sizes)."""
    monkeypatch.setattr(low_pass, "MIN_SHARED_BLOCKS", 0)  # short columns too, so np.convolve stays quick
    rng = np.random.default_rng(31)
    for _ in range(40):
        rate = float(rng.choice([50, 300, 1000]))
        cutoff = float(rng.uniform(0.02, 0.2)) * rate
        decimation = int(rng.integers(1, 40))
        filters = [ParallelFilter(cutoff * factor, rate, decimation, "test") for factor in (1.0, 0.5, 2.0)]
        longest = max(len(reference_taps(f.cutoff, rate)) for f in filters) // 2
        count = int(rng.integers(longest + 2, longest + 5000))
        size = shared_size(filters, count)
        assert size is not None and size % decimation == 0
        column = np.cumsum(rng.normal(size=count)) + 3.0  # a drifting column with an offset
        for chosen, out in zip(filters, low_passed_together(column, filters, size)):
            expected, _ = low_passed_rows(column, reference_taps(chosen.cutoff, rate), decimation, rate,
                                          chosen.cutoff)
            np.testing.assert_allclose(out, expected, rtol=0, atol=1e-12 * np.max(np.abs(column)))


def test_filters_that_cannot_share_a_spectrum_are_applied_apart():
    """Another decimation, a log shorter than MIN_SHARED_BLOCKS blocks (or than the longest filter's half) or a
    decimation with a large prime factor gives no shared size, and the outputs are each filter's own."""
    chosen = ParallelFilter(2.0, 1000.0, 10, "test")
    together = [chosen, ParallelFilter(1.0, 1000.0, 10, "test")]
    size = shared_size(together, 1_000_000)
    assert size % 10 == 0 and size >= 4 * len(together[1].design.taps)
    assert shared_size(together, low_pass.MIN_SHARED_BLOCKS * size - 1) is None  # too short to gain
    assert shared_size([chosen, ParallelFilter(1.0, 1000.0, 20, "test")], 1_000_000) is None
    assert shared_size([chosen, ParallelFilter(1.0, 1000.0, 10, "test")], chosen.design.half) is None
    assert shared_size([ParallelFilter(0.4, 1000.0, 997, "test")], 10_000_000) is None
    column = np.random.default_rng(5).normal(size=3000)
    np.testing.assert_array_equal(low_passed_together(column, [chosen], None)[0], chosen.apply_column(column))


def test_one_filter_on_both_sides_keeps_the_model_exact():
    """L(X theta) = L(X) theta for hand-built columns, including a sign column and a constant."""
    rng = np.random.default_rng(2)
    t = np.arange(5000) / 500.0
    q = 0.9 * np.sin(0.7 * t) + 0.3 * np.sin(2.9 * t + 1)
    X = np.column_stack([np.gradient(np.gradient(q, t), t), G * np.cos(q), np.gradient(q, t),
                         np.sign(np.gradient(q, t)), np.ones_like(t)])
    theta = rng.normal(size=5)
    chosen = ParallelFilter(4.0, 500.0, 62, "test")
    np.testing.assert_allclose(chosen.apply_column(X @ theta), chosen.apply(X) @ theta, rtol=0, atol=1e-11)
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
    logs = fit_logs(joint_log_from_table(table_of(data)), filtering=FilterRequest(2.0), sensitivity=False,
                    exclusion=ExclusionRequest(robust=False))
    np.testing.assert_allclose(logs.result.estimate, [0.8, 0.4, 0.15], rtol=1e-9)


def reference_band(q, step, share=0.95):
    """The frequency below which `share` of the Hann-windowed power of (cos q, sin q) lies, by numpy's FFT."""
    window = np.hanning(len(q))
    size = 1 << int(np.ceil(np.log2(len(q))))
    power = sum(np.abs(np.fft.rfft((part - part.mean()) * window, size)) ** 2 for part in (np.cos(q), np.sin(q)))
    cumulative = np.cumsum(power) / power.sum()
    return np.fft.rfftfreq(size, step)[np.searchsorted(cumulative, share)]


def test_the_automatic_cutoff_is_three_bands_of_the_motion_and_keeps_twenty_samples_per_hertz():
    t = np.arange(20_001) * 0.001
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)
    chosen = choose_filter(FilterRequest(), 0.001, True, q, len(q))
    band = reference_band(q, 0.001)
    assert 0.2 < band < 0.5  # the motion's sines are at 0.21 and 0.43 Hz
    assert chosen.cutoff == pytest.approx(3 * band, rel=1e-12)
    assert chosen.decimation == int(1000 / (20 * chosen.cutoff))
    assert "automatic: 3 x" in chosen.reason and "95% of the motion's power" in chosen.reason
    # A joint that turns over and over: q runs away, (cos q, sin q) keeps its band at the turning rate.
    spinning = 2 * np.pi * 0.5 * t + 0.2 * np.sin(2 * np.pi * 0.1 * t)
    assert 1.2 < choose_filter(FilterRequest(), 0.001, True, spinning, len(t)).cutoff < 2.0
    # At least 4 cycles per log, and at most a tenth of the rate.
    fast = 0.3 * np.sin(2 * np.pi * 8.0 * np.arange(2001) * 0.01)  # 8 Hz at 100 Hz: 3 bands pass 10 Hz
    held_down = choose_filter(FilterRequest(), 0.01, True, fast, 2001)
    assert held_down.cutoff == pytest.approx(10.0) and "held to 10 Hz" in held_down.reason
    held = choose_filter(FilterRequest(), 0.001, True, np.zeros(1000), 1000)
    assert not held.active and "no motion" in held.reason


def test_the_noise_cap_falls_as_the_angles_noise_floor_rises():
    """q's white noise, twice differentiated, grows as f^5 below the cutoff: more noise, a lower cap."""
    t = np.arange(20_001) * 0.001
    q = 0.5 * np.sin(2 * np.pi * 0.5 * t)
    size = 1 << 15
    frequencies, window = np.fft.rfftfreq(size, 0.001), np.hanning(len(t))
    caps = [noise_cap(q + np.random.default_rng(1).normal(0, sigma, len(t)), 0.001, 1.5, frequencies, window, size)
            for sigma in (1e-5, 1e-4, 1e-3)]
    assert caps[0] > caps[1] > caps[2]
    assert caps[1] / caps[2] == pytest.approx(10 ** (2 / 5), rel=0.1)  # noise power x 100: cap / 100^(1/5)


def test_off_and_given_settings(capsys, tmp_path):
    data = full_log()
    path = tmp_path / "log.csv"
    names = list(data)
    path.write_text(",".join(names) + "\n" + "".join(
        ",".join(repr(float(data[n][i])) for n in names) + "\n" for i in range(len(data["t"]))))
    assert main(["fit", "--csv", str(path), "--json", "--cutoff", "0", "--model", "plain", "--no-robust"]) == 0
    off = json.loads(capsys.readouterr().out)
    assert off["low_pass"]["cutoff_hz"] is None and off["samples"] == len(data["t"])
    assert main(["fit", "--csv", str(path), "--json", "--cutoff", "4", "--decimate", "3"]) == 0
    given = json.loads(capsys.readouterr().out)
    low_pass = given["low_pass"]
    assert (low_pass["cutoff_hz"], low_pass["decimation"]) == (4.0, 3)
    taps = len(reference_taps(4.0, 200.0))
    assert (low_pass["taps"], low_pass["edge_extension_samples"]) == (taps, (taps - 1) // 2)
    assert (low_pass["passband_edge_hz"], low_pass["stopband_edge_hz"]) == (2.0, 6.0)
    kept = len(range(0, len(data["t"]), 3))
    assert given["samples"] + round(given["exclusions"]["standstill_share"] * kept) \
        + round(given["exclusions"]["outside_torque_share"] * kept) == kept
    cutoffs = [s["cutoff_hz"] for s in given["sensitivity"]["settings"]]
    assert cutoffs == [4.0, 2.0, 8.0]  # nothing differentiated: only the cutoff is varied


@pytest.mark.parametrize("options, words", [
    (["--cutoff", "100"], "cutoff must be below the Nyquist frequency 100 Hz of this log; got 100"),
    (["--cutoff", "-1"], "argument --cutoff: must be a number of hertz, 0 (off) or more"),
    (["--decimate", "0"], "argument --decimate"),
    (["--cutoff", "0.1"], "cannot be low-passed: the cutoff 0.1 Hz needs more than"),
    # Decimations that keep fewer samples than a fit needs were fitted and blamed on the data (or, from 2^63 on,
    # a traceback): 401 samples keep 50 at most every 8th.
    (["--decimate", "9"], "cannot be decimated by 9: it keeps 45 of its 401 samples, and a fit needs at least 50: "
                          "decimate by at most 8"),
    (["--decimate", "1000000"], "cannot be decimated by 1,000,000: it keeps 1 of its 401 samples"),
    (["--decimate", str(2**63)], f"cannot be decimated by {2**63:,}: it keeps 1"),
    (["--decimate", "1" + "0" * 40], "it keeps 1 of its 401 samples"),
    (["--cutoff", "0", "--decimate", "400"], "cannot be decimated by 400"),
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
    assert main(["fit", "--csv", str(path), "--json", "--model", "plain"]) == 0
    check = json.loads(capsys.readouterr().out)["sensitivity"]
    assert check["exact_fit"] is (noise == 0.0)
    assert check["flagged"] is False
    if noise == 0.0:
        assert max(check["largest_relative_move"].values()) < 1e-12
        assert main(["fit", "--csv", str(path), "--model", "plain"]) == 0
        text = capsys.readouterr().out
        assert "fitted exactly (noise-free data)" in text and "decide this estimate" not in text
    else:
        assert all(move is not None for move in check["largest_move_std_errors"].values())


def test_the_note_names_the_filter_and_counts_in_ordinals():
    chosen = ParallelFilter(5.0, 200.0, 21, "cutoff given")
    taps = len(reference_taps(5.0, 200.0))
    assert low_pass_note(chosen) == (
        f"torque and every regressor column low-passed alike at 5 Hz (zero-phase FIR, Kaiser-windowed sinc, "
        f"{taps} taps, Kaiser beta 6.2: flat within 0.1% below 2.5 Hz, 60 dB down above 7.5 Hz; each end "
        f"extended by {(taps - 1) // 2} samples, reflected about a line fitted to its last half cutoff period, so "
        f"no sample is lost), then every 21st sample kept (cutoff given); the training RMSE is of the filtered "
        f"torque.")
    assert low_pass_short_note(chosen) == "torque and regressor low-passed at 5 Hz, every 21st sample kept"
    assert ", every 22nd sample" in low_pass_short_note(ParallelFilter(5.0, 200.0, 22, ""))
    assert ", every 12th sample" in low_pass_short_note(ParallelFilter(5.0, 200.0, 12, ""))


def test_a_constant_column_comes_out_as_the_constant_the_filter_gives_to_rounding():
    """A torque bias's column is skipped by the filter (its taps sum to 1): what the filter computes for it, with
    scipy's own convolution of the extended column as the reference, is the constant to rounding."""
    chosen = ParallelFilter(2.0, 1000.0, 7, "cutoff given")
    column = np.full(20_000, 2.5)
    out = chosen.apply_column(column)
    assert out.shape == (len(chosen.rows(len(column))),) and np.all(out == 2.5)
    from scipy.signal import fftconvolve

    half = chosen.design.half
    reference = fftconvolve(np.full(len(column) + 2 * half, 2.5), chosen.design.taps[::-1], mode="valid")[::7]
    np.testing.assert_allclose(out, reference, rtol=1e-12)
