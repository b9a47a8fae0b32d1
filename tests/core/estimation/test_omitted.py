"""The omitted-terms test: its chi-squared tail against scipy, its Wald statistic against a Newey-West written
here, and on logs: a Coulomb friction the model lacks is found and named, a model that has it is left alone."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats
from support.coulomb_joint import coulomb_joint_log

from jointid.estimation.omitted import chi_squared_tail, omitted_terms_test


@pytest.mark.parametrize("dof", [1, 2, 3, 4, 5, 6, 9])
@pytest.mark.parametrize("statistic", [0.0, 0.3, 2.0, 7.5, 30.0, 120.0])
def test_the_chi_squared_tail_matches_scipy(statistic, dof):
    assert chi_squared_tail(statistic, dof) == pytest.approx(stats.chi2.sf(statistic, dof), rel=1e-9, abs=1e-300)


def newey_west_covariance(W, residuals, lag):
    """(W'W)^-1 S (W'W)^-1 with Bartlett weights, by the textbook double sum (no FFT)."""
    scores = W * residuals[:, None]
    meat = scores.T @ scores
    for k in range(1, lag + 1):
        weight = 1 - k / (lag + 1)
        cross = scores[k:].T @ scores[:-k]
        meat += weight * (cross + cross.T)
    bread = np.linalg.inv(W.T @ W)
    return bread @ meat @ bread


def test_the_wald_statistic_and_the_moves_match_a_reference():
    rng = np.random.default_rng(4)
    n = 400
    t = np.arange(n) / 20
    x = np.column_stack([np.sin(t), np.cos(0.7 * t), np.ones(n)])
    z = np.column_stack([np.sign(np.sin(t)), np.sin(t) * np.abs(np.sin(t))])
    noise = np.convolve(rng.standard_normal(n + 9), np.ones(10) / 10, mode="valid")
    tau = x @ [1.0, 0.5, 0.2] + 0.05 * z[:, 0] + 0.1 * noise
    lag = 12
    test = omitted_terms_test(x, z, tau, np.arange(n), lag, ("a", "b", "c"), ("s", "q"))
    W = np.column_stack([x, z])
    wide = np.linalg.lstsq(W, tau, rcond=None)[0]
    covariance = newey_west_covariance(W, tau - W @ wide, lag)[3:, 3:]
    assert test.statistic == pytest.approx(wide[3:] @ np.linalg.solve(covariance, wide[3:]), rel=1e-8)
    assert test.p_value == pytest.approx(stats.chi2.sf(test.statistic, 2), rel=1e-8)
    base = np.linalg.lstsq(x, tau, rcond=None)[0]
    errors = np.sqrt(np.diag(newey_west_covariance(x, tau - x @ base, lag)))
    assert test.moves == pytest.approx(np.abs(wide[:3] - base) / errors, rel=1e-8)


@pytest.mark.parametrize("seed", [1, 2])
def test_a_coulomb_friction_the_model_lacks_is_found_and_named(seed):
    from jointid import fit_log

    plain = fit_log(coulomb_joint_log(seed), model="plain", sensitivity=False)
    assert plain.omitted.found and plain.omitted.followed == ("Fc",)
    assert "B" in plain.decided_by_omitted  # friction's sign(qd) resembles qd: damping absorbs it
    assert plain.unsettled["B"] == "moved by a term the model lacks"
    assert "The residuals follow Coulomb friction (sign qd), which the model lacks" in plain.summary()
    assert "--model coulomb" in plain.summary()
    # The default model has it: nothing is found, no verdict is touched.
    default = fit_log(coulomb_joint_log(seed), sensitivity=False)
    assert not default.omitted.found and default.decided_by_omitted == ()
