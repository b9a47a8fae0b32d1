"""The sign-constrained fit, against scipy.optimize.lsq_linear on the same (hand-built) problem."""

from __future__ import annotations

import json

import numpy as np
import pytest
import support.physics_reference as ref
from hypothesis import given
from hypothesis import settings as hypothesis_settings
from hypothesis import strategies as st
from scipy.optimize import lsq_linear

from jointid.cli import main
from jointid.estimation.bounded import INERTIA_FLOOR, bounded_least_squares, lower_bounds
from jointid.estimation.solver import solve_least_squares
from jointid.model.terms import model_named
from jointid.present.status import compact_status, status_message
from jointid.studies.experiment import run_experiment
from jointid.studies.sweep import run_sweep
from jointid.synthetic.settings import Settings


def slow_problem(noise=0.2, seed=7):
    """The slow motion's regressor and noisy torques, built by hand."""
    t = np.linspace(0.0, 8.0, 24)
    q, qd, qdd = 0.08 * np.sin(0.4 * t), 0.08 * 0.4 * np.cos(0.4 * t), -0.08 * 0.16 * np.sin(0.4 * t)
    tau = ref.measured(q, qd, qdd) + ref.noise(noise, 24, [seed])[0]
    return ref.regressor("plain", q, qd, qdd), tau


def test_slow_motion_constrained_holds_the_inertia_at_its_floor_like_lsq_linear():
    X, tau = slow_problem()
    expected = lsq_linear(X, tau, bounds=([INERTIA_FLOOR, 0, 0], np.inf), method="bvls", tol=1e-15).x
    constrained = run_experiment(Settings(motion="slow", noise=0.2, constrained=True))
    unconstrained = run_experiment(Settings(motion="slow", noise=0.2))
    np.testing.assert_allclose(constrained.estimate, expected, rtol=1e-9, atol=1e-12)
    assert constrained.at_bound == ("I",) and constrained.estimate[0] == INERTIA_FLOOR
    assert abs(constrained.training_rmse - unconstrained.training_rmse) < 0.001
    rich = run_experiment(Settings(motion="rich", noise=0.2))
    assert constrained.heldout_rmse > 10 * rich.heldout_rmse  # correct signs are not accuracy
    assert constrained.uncertainty.verdicts[0] == "at bound"
    assert "correct signs are not accuracy" in status_message(constrained)


def test_an_inactive_constraint_is_the_unconstrained_fit_bit_for_bit():
    free = run_experiment(Settings(noise=0.2))
    held = run_experiment(Settings(noise=0.2, constrained=True))
    assert held.at_bound == () and np.array_equal(held.estimate, free.estimate)
    assert "no bound is active" in status_message(held)


def test_the_compact_status_names_what_the_constraint_and_the_verdicts_did():
    """The explorer's short status on a small screen: the bound held, the sign failures and verdicts, by name."""
    held = run_experiment(Settings(motion="slow", noise=0.2, constrained=True))
    free = run_experiment(Settings(motion="slow", noise=0.2))
    inactive = run_experiment(Settings(noise=0.2, constrained=True))
    assert compact_status(held).startswith(
        f"Rank 3 of 3: a unique fit, held-out RMSE {held.heldout_rmse:.6f} N m. Sign rules: I held at the bound.")
    assert "Fitted I fails its sign rule." in compact_status(free) and free.estimate[0] < 0
    assert "Sign rules: no bound active." in compact_status(inactive)
    assert all(len(compact_status(result)) <= 3 * 78 for result in (held, free, inactive))  # three rows at 80


@hypothesis_settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), noise=st.floats(0.01, 2.0), model=st.sampled_from(["plain", "coulomb", "bias",
                                                                                           "coulomb+bias"]))
def test_bounded_solutions_match_lsq_linear(seed, noise, model):
    t = np.linspace(0.0, 8.0, 30)
    q, qd, qdd = 0.1 * np.sin(0.5 * t), 0.05 * np.cos(0.5 * t), -0.025 * np.sin(0.5 * t)
    X = ref.regressor(model, q, qd, qdd)
    tau = ref.measured(q, qd, qdd) + ref.noise(noise, 30, [seed])[0]
    joint_model = model_named(model)
    lower = lower_bounds(joint_model)
    ours = bounded_least_squares(solve_least_squares(X, tau), lower)
    theirs = lsq_linear(X, tau, bounds=(lower, np.inf), method="bvls", tol=1e-15).x
    cost = lambda theta: np.sum((tau - X @ theta) ** 2)  # noqa: E731
    assert cost(ours.estimate) <= cost(theirs) * (1 + 1e-9) + 1e-15
    assert (ours.estimate >= lower).all()


def test_a_constrained_sweep_is_active_in_two_thirds_of_slow_seeds_and_never_on_rich():
    slow = run_sweep(Settings(motion="slow", noise=0.2, constrained=True), 5000)
    rich = run_sweep(Settings(motion="rich", noise=0.2, constrained=True), 5000)
    assert slow.constraint_active_fraction == pytest.approx(2 / 3, abs=0.05)
    assert rich.constraint_active_fraction == 0.0
    assert slow.sign_failure_fraction == 0.0
    # The same fraction from the unconstrained seeds that break a sign rule (independent of the bounded solver).
    free = run_sweep(Settings(motion="slow", noise=0.2), 5000)
    assert slow.constraint_active_fraction == pytest.approx(free.sign_failure_fraction, abs=0.01)


def test_constrained_json_shows_the_bound_beside_the_unconstrained_estimate(capsys):
    assert main(["fit", "--motion", "slow", "--noise", "0.2", "--constrained", "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["constrained"] is True and document["at_bound"] == ["I"]
    assert document["std_error"]["I"] is None and document["verdicts"]["I"] == "at bound"
    assert round(document["unconstrained_estimate"]["I"], 6) == -1.607788
    assert main(["fit", "--motion", "slow", "--noise", "0.2", "--constrained"]) == 0
    out = capsys.readouterr().out
    assert "at bound (no standard error)" in out and "Without the sign constraint the fit is I -1.607788" in out
