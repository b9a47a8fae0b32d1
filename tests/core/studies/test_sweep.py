"""Seed sweep: one factorisation for K seeds, equal to a per-seed loop, with honest statistics."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from jointid.estimation.solver import solve_least_squares
from jointid.present.tables import sweep_message
from jointid.studies.experiment import run_experiment
from jointid.studies.sweep import SweepCancelled, run_sweep
from jointid.synthetic.settings import Settings

SLOW = Settings(motion="slow", noise=0.2, seed=7)


def per_seed_loop(settings, seeds):
    """The naive way: run_experiment once per seed; (estimates (3, K), training RMSE, held-out RMSE, failures)."""
    results = [run_experiment(Settings(settings.motion, settings.noise, settings.samples, int(s))) for s in seeds]
    estimates = np.array([r.estimate for r in results]).T.copy()
    training = np.array([r.training_rmse for r in results])
    heldout = np.array([r.heldout_rmse for r in results])
    failing = np.array([bool(r.sign_failures) for r in results])
    return estimates, training, heldout, failing


@pytest.mark.parametrize(
    "settings, chunk_size",
    [(SLOW, None), (Settings(motion="rich", noise=0.2, seed=1000), 7), (Settings(motion="rich", noise=1.5, samples=50, seed=3), None)],
)
def test_sweep_equals_a_per_seed_loop_exactly(settings, chunk_size):
    sweep = run_sweep(settings, 300, chunk_size=chunk_size)
    estimates, training, heldout, failing = per_seed_loop(settings, range(settings.seed, settings.seed + 300))
    np.testing.assert_array_equal(sweep.seeds, np.arange(settings.seed, settings.seed + 300))
    np.testing.assert_array_equal(sweep.estimates, estimates)
    np.testing.assert_array_equal(sweep.training_rmse, training)
    np.testing.assert_array_equal(sweep.heldout_rmse, heldout)
    for name, values in [("I", estimates[0]), ("h", estimates[1]), ("B", estimates[2]),
                         ("training_rmse", training), ("heldout_rmse", heldout)]:
        distribution = sweep.statistics[name]
        assert distribution.mean == np.mean(values)
        assert distribution.std == np.std(values, ddof=1)
        assert (distribution.p5, distribution.p50, distribution.p95) == tuple(np.percentile(values, [5, 50, 95]))
    assert sweep.sign_failure_fraction == np.mean(failing)


def test_many_right_hand_sides_equal_single_solves_bit_for_bit():
    rng = np.random.default_rng(5)
    X = rng.normal(size=(40, 3)) * [1e-3, 1.0, 1e3]
    Y = rng.normal(size=(40, 25))
    many = solve_least_squares(X, Y)
    assert many.qty.shape == (3, 25) and many.residual_norm.shape == (25,) and many.estimate.shape == (3, 25)
    for k in range(25):
        one = solve_least_squares(X, Y[:, k])
        assert isinstance(one.residual_norm, float) and one.qty.shape == (3,)
        np.testing.assert_array_equal(many.estimate[:, k], one.estimate)
        np.testing.assert_array_equal(many.qty[:, k], one.qty)
        assert many.residual_norm[k] == pytest.approx(one.residual_norm, rel=1e-14)


def test_chunking_does_not_change_any_number():
    whole = run_sweep(SLOW, 100)
    chunked = run_sweep(SLOW, 100, chunk_size=9)
    np.testing.assert_array_equal(whole.estimates, chunked.estimates)
    np.testing.assert_array_equal(whole.heldout_rmse, chunked.heldout_rmse)


def test_slow_motion_reference_figures_for_seeds_7_to_5006():
    sweep = run_sweep(SLOW, 5000)
    assert (int(sweep.seeds[0]), int(sweep.seeds[-1])) == (7, 5006)
    negative_inertia = float(np.mean(sweep.estimates[0] <= 0))
    assert 0.43 <= negative_inertia <= 0.46  # "about 44 %"
    assert sweep.sign_failure_fractions["I"] == negative_inertia
    assert sweep.statistics["I"].std == pytest.approx(5.425077, rel=0.03)  # "within a few %"


@pytest.mark.parametrize("settings", [SLOW, Settings(motion="rich", noise=0.2, seed=1000)])
def test_empirical_std_agrees_with_expected_within_sampling_error(settings):
    count = 20_000
    sweep = run_sweep(settings, count)
    # For near-normal estimates the sample std has relative standard error 1/sqrt(2(K-1)) = 0.5 %;
    # allow four of them.
    tolerance = 4 / np.sqrt(2 * (count - 1))
    np.testing.assert_allclose(sweep.empirical_std, sweep.noise_bound_std_error, rtol=tolerance)


def test_holds_sweep_has_no_estimates_and_says_so():
    sweep = run_sweep(Settings(motion="holds", noise=0.2), 50)
    assert sweep.rank == 1 and sweep.estimates is None and sweep.statistics == {}
    assert sweep.sign_failure_fraction is None and sweep.empirical_std is None
    assert "rank 1 of 3 for every seed" in sweep_message(sweep) and "no estimates" in sweep_message(sweep)


def test_seeds_wrap_past_2_to_the_32_like_the_generator():
    settings = Settings(motion="rich", noise=0.2, seed=2**32 - 2)
    sweep = run_sweep(settings, 4)
    assert sweep.seeds.tolist() == [2**32 - 2, 2**32 - 1, 0, 1]
    estimates, *_ = per_seed_loop(settings, [2**32 - 2, 2**32 - 1, 0, 1])
    np.testing.assert_array_equal(sweep.estimates, estimates)


def test_progress_reports_every_chunk_and_cancel_stops_the_sweep():
    calls = []
    run_sweep(SLOW, 25, chunk_size=10, progress=lambda done, total: calls.append((done, total)))
    assert calls == [(10, 25), (20, 25), (25, 25)]
    checks = iter([False, True])
    with pytest.raises(SweepCancelled):
        run_sweep(SLOW, 25, chunk_size=10, cancelled=lambda: next(checks))


def test_single_seed_has_no_standard_deviation():
    sweep = run_sweep(SLOW, 1)
    assert sweep.statistics["I"].std is None and sweep.empirical_std is None
    assert sweep.statistics["I"].mean == run_experiment(SLOW).estimate[0]


@pytest.mark.parametrize("count", [0, -1, 1_000_001, 2.5, True])
def test_bad_seed_counts_are_refused(count):
    with pytest.raises(ValueError, match="seed count"):
        run_sweep(SLOW, count)


@given(st.lists(st.floats(allow_nan=True, allow_infinity=False, width=64), min_size=1, max_size=60),
       st.lists(st.floats(0, 100), min_size=1, max_size=5))
def test_percentiles_are_numpys(values, levels):
    # The sweep's summary must not move by a bit from np.percentile's default (linear) method.
    from jointid.studies.sweep import percentiles

    values = np.array(values)
    with np.errstate(invalid="ignore", over="ignore"):
        expected = np.percentile(values, levels)
        got = percentiles(values, levels)
    np.testing.assert_array_equal(got, expected)


def test_the_sweep_table_reads_rounding_as_zero_and_keeps_its_fixed_decimals(capsys):
    """Noise 0: every fit is exact, and the held-out RMSE's spread over the seeds is rounding (about 1e-31); the table
    shows it as 0.000000 among its fixed decimals, and a real spread (noise 0.2) still shows in full."""
    from jointid.cli import main

    assert main(["sweep", "--noise", "0", "--seeds", "50"]) == 0
    table = capsys.readouterr().out
    assert "e-" not in table
    std_row = next(line for line in table.splitlines() if line.startswith("std (empirical)"))
    assert std_row.split()[2:] == ["0.000000"] * 5
    assert main(["sweep", "--noise", "0.2", "--seeds", "50"]) == 0
    std_row = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("std (empirical)"))
    assert all(float(value) > 0 for value in std_row.split()[2:])
