"""Time stamps as recorded: jitter resampled onto a uniform grid, exact repeats dropped, gaps/backwards/repeats refused."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import settings as hypothesis_settings
from hypothesis import strategies as st

from jointid.cli import main
from jointid.logs.csv_reader import load_log
from jointid.logs.table import LogError
from jointid.logs.timing import (
    GAP_FACTOR,
    MEDIAN_SAMPLE,
    SAMPLED_MEDIAN_MIN,
    UNIFORM_TOLERANCE,
    TimeProblem,
    check_times,
    median_in_place,
)


def write(tmp_path, columns: dict, name="log.csv"):
    """A CSV of the given columns (float-round-tripped cells)."""
    names = list(columns)
    rows = zip(*(columns[n] for n in names))
    text = ",".join(names) + "\n" + "".join(",".join(repr(float(v)) for v in row) + "\n" for row in rows)
    path = tmp_path / name
    path.write_text(text)
    return path


def jittered_times(rate: float, duration: float, jitter: float, seed: int = 1) -> np.ndarray:
    """Times i/rate shifted by up to +-jitter/2 of a step each (so steps vary by up to +-jitter)."""
    step = 1.0 / rate
    count = int(round(duration * rate)) + 1
    shift = np.random.default_rng(seed).uniform(-jitter / 2, jitter / 2, count) * step
    shift[0] = shift[-1] = 0.0
    return np.arange(count) * step + shift


def smooth(t):
    """A smooth angle and a torque, closed form."""
    return 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t), 2.0 + np.cos(0.9 * t)


def test_jittered_times_are_resampled_by_a_cubic_spline_onto_the_median_step(tmp_path):
    t = jittered_times(100, 10, 0.2)
    q, tau = smooth(t)
    log = load_log(write(tmp_path, {"t": t, "q": q, "tau": tau}), window=11, order=4)
    timing = log.timing
    steps = np.diff(t)
    median = np.median(steps)
    assert timing.resampled and timing.step == pytest.approx(median, rel=1e-12)
    assert timing.max_jitter == pytest.approx(np.max(np.abs(steps - median)) / median, rel=1e-9)
    assert timing.median_jitter == pytest.approx(np.median(np.abs(steps - median)) / median, rel=1e-9)
    assert 0.05 < timing.max_jitter <= 0.2
    # The fitted samples lie on the uniform grid and follow the closed form closely (a cubic's error).
    np.testing.assert_allclose(np.diff(log.data.t), median, rtol=1e-9)
    q_true, tau_true = smooth(log.data.t)
    assert np.max(np.abs(log.data.q - q_true)) < 1e-6
    assert np.max(np.abs(log.data.tau - tau_true)) < 1e-6
    note = next(n for n in log.notes if "resampled" in n)
    assert "cubic spline" in note and f"{timing.max_jitter:.1%} (max)" in note and f"{1 / timing.step:.6g} Hz grid" in note


def test_steps_within_the_tolerance_are_used_as_they_are(tmp_path):
    t = jittered_times(100, 5, UNIFORM_TOLERANCE / 2)
    q, tau = smooth(t)
    log = load_log(write(tmp_path, {"t": t, "q": q, "tau": tau}), window=11, order=4)
    assert not log.timing.resampled
    np.testing.assert_array_equal(log.data.t, t)  # nothing trimmed
    assert not any("resampled" in n for n in log.notes)


def test_a_log_with_both_derivatives_keeps_its_jittered_times(tmp_path):
    t = jittered_times(100, 2, 0.3)
    q, tau = smooth(t)
    log = load_log(write(tmp_path, {"t": t, "q": q, "qd": q, "qdd": q, "tau": tau}))
    np.testing.assert_array_equal(log.data.t, t)
    assert not log.timing.resampled and log.notes == ()


def test_a_log_with_both_derivatives_may_have_gaps_but_not_run_backwards(tmp_path):
    t = np.array([0.0, 0.1, 0.2, 5.0, 5.1])
    log = load_log(write(tmp_path, {"t": t, "q": t, "qd": t, "qdd": t, "tau": t}))
    np.testing.assert_array_equal(log.data.t, t)
    back = np.array([0.0, 0.1, 0.2, 0.15, 0.3])
    with pytest.raises(LogError, match=r"row 5, column 1 \(t\): time runs backwards: t = 0.15 s after 0.2 s"):
        load_log(write(tmp_path, {"t": back, "q": t, "qd": t, "qdd": t, "tau": t}))


def test_rows_repeated_exactly_are_dropped_and_counted(tmp_path):
    t = np.arange(300) * 0.01
    q, tau = smooth(t)
    keep = np.insert(np.arange(300), [100, 200, 200], [99, 199, 199])  # row 99 twice, row 199 three times
    log = load_log(write(tmp_path, {"t": t[keep], "q": q[keep], "tau": tau[keep]}), window=11, order=4)
    assert log.timing.duplicates == 3 and log.rows == 303 and log.data.count == 300
    np.testing.assert_array_equal(log.data.t, t)
    assert any("3 rows repeating the previous row exactly (time and values) dropped." in n for n in log.notes)


def test_a_stamp_repeated_with_other_values_cannot_be_ordered(tmp_path):
    t = np.arange(300) * 0.01
    q, tau = smooth(t)
    t[150] = t[149]
    with pytest.raises(LogError, match=r"row 152, column 1 \(t\): time stamp t = 1.49 s repeats with other values"):
        load_log(write(tmp_path, {"t": t, "q": q, "tau": tau}))


def test_a_gap_is_refused_with_its_times_but_a_step_just_below_the_factor_is_jitter():
    t = np.arange(100) * 0.01
    columns = {"t": t, "q": np.sin(t)}
    below = t.copy()
    below[50:] += (GAP_FACTOR - 1.01) * 0.01
    _, check = check_times(below, {**columns, "t": below}, uniform=True)
    assert check.resampled
    above = t.copy()
    above[50:] += (GAP_FACTOR - 0.99) * 0.01
    with pytest.raises(TimeProblem, match=r"gap in time: 0.0501 s between t = 0.49 s and 0.5401 s") as caught:
        check_times(above, {**columns, "t": above}, uniform=True)
    assert caught.value.index == 50
    _, check = check_times(above, {**columns, "t": above}, uniform=False)  # nothing to differentiate: kept
    assert not check.resampled


def test_the_gap_row_counts_rows_dropped_before_it():
    t = np.r_[np.arange(50) * 0.01, 0.49, 0.49, 1.0 + np.arange(10) * 0.01]
    with pytest.raises(TimeProblem) as caught:
        check_times(t, {"t": t, "q": np.zeros_like(t)}, uniform=True)
    assert caught.value.index == 52  # the row in the file, not in the deduplicated columns


@pytest.mark.parametrize("name, times, words", [
    ("gap", np.r_[np.arange(200) * 0.01, 3.0 + np.arange(200) * 0.01], "gap in time"),
    ("backwards", np.r_[np.arange(200) * 0.01, 1.5 + np.arange(200) * 0.01], "time runs backwards"),
    ("duplicates", np.r_[np.arange(200) * 0.01, 1.99 + np.arange(200) * 0.01], "cannot be ordered"),
])
def test_time_errors_are_one_line_and_exit_2(tmp_path, capsys, name, times, words):
    q, tau = smooth(np.arange(len(times)) * 0.01)
    path = write(tmp_path, {"t": times, "q": q, "tau": tau}, f"{name}.csv")
    assert main(["fit", "--csv", str(path)]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and words in lines[0] and f"{name}.csv, row 202, column 1 (t)" in lines[0]
    assert captured.out == ""


def test_the_json_says_how_time_was_handled(tmp_path, capsys):
    import json

    t = jittered_times(100, 10, 0.2)
    q, tau = smooth(t)
    path = write(tmp_path, {"t": t, "q": q, "tau": tau})
    assert main(["fit", "--csv", str(path), "--window", "11", "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    timing = document["timing"]
    assert timing["resampled"] and timing["interpolation"] == "cubic spline"
    assert timing["median_step"] == pytest.approx(np.median(np.diff(t)), rel=1e-12)
    assert timing["rows_before"] == len(t) and document["heldout_timing"] is None
    assert any("resampled" in note for note in document["notes"])


def test_simulate_jitter_writes_the_true_instants_off_their_ticks(tmp_path, capsys):
    path = tmp_path / "robot.csv"
    argv = ["simulate", "--rate", "100", "--duration", "4", "--jitter", "0.2", "--encoder-counts", "4096",
            "--out", str(path)]
    assert main(argv) == 0
    values = np.loadtxt(path, delimiter=",", skiprows=2)
    t, q = values[:, 0], values[:, 1]
    ticks = np.arange(401) / 100
    off = (t - ticks) * 100
    assert np.all(np.abs(off) <= 0.2) and np.max(np.abs(off)) > 0.15 and off[0] == off[-1] == 0
    exact = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)  # the angle at the written instant, not the tick
    assert np.max(np.abs(q - exact)) <= np.pi / 4096 + 1e-12
    assert "sampling instants jittered by up to 0.2 steps" in path.read_text().splitlines()[0]


@hypothesis_settings(max_examples=300, deadline=None)
@given(st.lists(st.floats(-1e300, 1e300) | st.sampled_from([0.001, 0.001 + 2**-60, 0.0]), min_size=1, max_size=60))
def test_the_median_in_place_is_numpys_median(values):
    values = np.array(values)
    expected = np.median(values)
    assert median_in_place(values.copy()) == expected


def long_array(kind: str, count: int, seed: int) -> np.ndarray:
    """A long array of a shape that a median's sample might misjudge."""
    rng = np.random.default_rng(seed)
    stride = count // MEDIAN_SAMPLE  # the sample's spacing in median_in_place
    if kind == "steps":  # a 1 kHz clock's steps: a few distinct values
        return np.diff(np.arange(count + 1) * 1e-3)
    if kind == "ties":
        return rng.integers(0, 3, count).astype(float)
    if kind == "sorted":
        return np.sort(rng.standard_normal(count))
    if kind == "reversed":
        return np.sort(rng.standard_normal(count))[::-1].copy()
    if kind == "sample misses the middle":  # every sampled position holds a value far below the rest
        values = rng.uniform(1.0, 2.0, count)
        values[::stride] = -1e300
        return values
    return rng.standard_normal(count) * 10.0 ** rng.integers(-300, 300)


@hypothesis_settings(max_examples=60, deadline=None)
@given(st.sampled_from(["steps", "ties", "sorted", "reversed", "sample misses the middle", "normal"]),
       st.integers(SAMPLED_MEDIAN_MIN - 1, 3 * SAMPLED_MEDIAN_MIN), st.integers(0, 2**32 - 1))
def test_the_median_of_a_long_array_is_numpys_median(kind, count, seed):
    values = long_array(kind, count, seed)
    assert median_in_place(values.copy()) == np.median(values)


def test_the_time_checks_report_numpys_medians_of_the_steps_and_their_deviations():
    rng = np.random.default_rng(7)
    for count in (1000, 1001):  # even and odd numbers of steps
        t = np.cumsum(0.01 * (1 + 0.004 * rng.standard_normal(count + 1)))
        steps = np.diff(t)
        step = np.median(steps)
        deviation = np.abs(steps - step) / step
        _, check = check_times(t, {"t": t, "q": np.zeros(count + 1)}, uniform=False)
        assert check.step == step
        assert check.median_jitter == np.median(deviation)
        assert check.max_jitter == deviation.max()
