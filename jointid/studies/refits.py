"""Cheap refits that judge a log fit: without the robust step's exclusions, stretch by stretch, run by run.

Each refit reuses the fit's already filtered regressor columns (a row subset of
them), so it costs a least-squares solve and a Newey-West sum, never another
low-pass. What each finds is a jointid.estimation.judgement Spread or Scatter:

- robust: the fit with the outside torques the robust step found kept in
  (`--no-robust`, standstill still left out); its move beyond noise widens the
  error (beyond_noise), as the sensitivity check's refits do;
- stretches: the run cut into STRETCHES contiguous pieces (each far longer than
  the filter's support), each fitted alone; their scatter about the weighted
  mean, in their own standard errors, is chi-squared with STRETCHES - 1 degrees
  of freedom when the errors hold from one stretch to the next (Birge's ratio);
- runs: the same test of several runs' own fits about their pooled fit.

A scatter is counted only beyond the SCATTER_LEVEL quantile, so clean data
keep their verdicts (benchmarks/verdict_study.py measures how often).
"""

from __future__ import annotations

import math

import numpy as np

from ..estimation.judgement import Scatter, Spread
from ..estimation.solver import solve_least_squares
from ..estimation.uncertainty import covariance_factor, newey_west, parameter_uncertainty

STRETCHES = 2
"""A single run is cut into this many contiguous stretches (halves) for the stretch-to-stretch scatter. Thirds
were tried first: each third's Newey-West errors, from a few dozen independent samples, came out too small, and
their scatter flagged 28 of 100 parameters of clean synthetic joints at the 5 % level (halves: 9; at 1 %, 1)."""
SCATTER_LEVEL = 0.99
"""A scatter counts when its chi-squared statistic exceeds this quantile (nominally a 1 % false alarm per
parameter; benchmarks/verdict_study.py measures it on clean joints)."""
NORMAL_QUANTILE = 2.3263478740408408
"""The standard normal's SCATTER_LEVEL quantile, for the Wilson-Hilferty chi-squared quantile."""


NORMAL_QUANTILE_TWO_SIDED = 2.5758293035489004
"""The standard normal's (1 + SCATTER_LEVEL) / 2 quantile."""


def chi_squared_quantile(dof: int) -> float:
    """The chi-squared distribution's SCATTER_LEVEL quantile with `dof` degrees of freedom (Wilson-Hilferty: within
    2.5 % of the exact value from one degree of freedom up; numpy has no chi-squared quantile, scipy costs 0.3 s)."""
    if dof == 2:
        return -2.0 * math.log(1 - SCATTER_LEVEL)  # exact: the chi-squared of two degrees is exponential
    if dof == 1:
        return NORMAL_QUANTILE_TWO_SIDED ** 2  # exact: the square of a standard normal
    a = 2.0 / (9 * dof)
    return dof * (1 - a + NORMAL_QUANTILE * math.sqrt(a)) ** 3


def is_exact(result) -> bool:
    """True when a fit reproduces its torques to rounding (noise-free data, the sensitivity check's EXACT_FIT): its
    standard errors are rounding too, and a move or a scatter in them says nothing."""
    from ..norms import rms  # without overflow for torques of extreme magnitude
    from .sensitivity import EXACT_FIT

    rmse = result.training_rmse
    return rmse is not None and rmse <= EXACT_FIT * rms(result.training.tau)


def scatter_ratios(values: np.ndarray, errors: np.ndarray, centre: np.ndarray | None = None
                   ) -> tuple[np.ndarray, np.ndarray]:
    """(Birge ratios, significant) per parameter of (k, p) `values` with standard errors `errors`, about `centre`
    (default their inverse-variance weighted mean); either centre is fitted to the pieces, costing a degree of
    freedom."""
    with np.errstate(all="ignore"):  # errors of extreme magnitude: a non-finite statistic counts as no scatter
        weights = 1.0 / np.square(errors)
        mean = np.sum(weights * values, axis=0) / np.sum(weights, axis=0) if centre is None else centre
        statistic = np.sum(weights * np.square(values - mean), axis=0)
    dof = len(values) - 1  # a pooled centre is fitted from the same pieces too
    with np.errstate(all="ignore"):
        ratio = np.sqrt(statistic / dof)
    return ratio, np.isfinite(statistic) & (statistic > chi_squared_quantile(dof))


def scatter_findings(names, ratios: np.ndarray, significant: np.ndarray, pieces: str) -> tuple[Scatter, ...]:
    """A Scatter for each parameter whose pieces scatter significantly beyond their standard errors."""
    return tuple(Scatter(name, float(ratio), pieces)
                 for name, ratio, counted in zip(names, ratios, significant) if counted and ratio > 1)


CHOICE_MOVE = 2.0
"""Another analysis choice widens an error only when it moves the estimate by more than this many standard errors of
the two fits' noise (the sensitivity check's threshold): below it, moves are what noise makes, and counting them
widened clean synthetic joints' errors by a quarter to a half (benchmarks/verdict_study.py)."""

ROBUST_CHOICE = "the robust step's exclusions (--no-robust)"
"""What widened an error that the fit with the robust step's outside torques kept in moves beyond noise."""


def beyond_noise(names, estimate: np.ndarray, noise: np.ndarray, others, choice: str, other_errors=None
                 ) -> tuple[Spread, ...]:
    """A Spread per parameter that another analysis choice's estimates `others` (k, p) move further than noise
    would: a move counts beyond CHOICE_MOVE of its noise standard errors, and widens by what noise leaves of it,
    sqrt(move^2 - noise var). Two fits of one run differ by noise of variance |se_other^2 - se^2| when one uses
    information the other lacks (Hausman), at least se^2 (`other_errors`: the others' (k, p) noise errors, None:
    se^2 alone)."""
    if not len(others):
        return ()
    others = np.atleast_2d(np.asarray(others, dtype=float))
    noise = np.asarray(noise, dtype=float)
    with np.errstate(all="ignore"):  # estimates of extreme magnitude: a non-finite move widens nothing
        variance = np.square(noise)
        moves = np.abs(others - estimate)
        allowed = np.broadcast_to(variance, moves.shape).copy()
        for k, errors in enumerate(other_errors or ()):
            if errors is not None:
                allowed[k] = np.maximum(variance, np.abs(np.square(np.asarray(errors, dtype=float)) - variance))
        counted = np.isfinite(moves) & np.isfinite(allowed) & (moves > CHOICE_MOVE * np.sqrt(allowed))
        extra = np.where(counted, np.sqrt(np.maximum(np.square(moves) - allowed, 0.0)), 0.0)
        largest = np.max(extra, axis=0)
    return tuple(Spread(name, float(value), choice) for name, value in zip(names, largest)
                 if np.isfinite(value) and value > 0)


def robust_spreads(result, exclusions, by_hand: np.ndarray) -> tuple[Spread, ...]:
    """How far the fit with the robust step's outside torques kept in moves each parameter beyond noise
    (`by_hand`: the samples left out by hand, still left out); () when the step left nothing out."""
    kept_in = robust_refit(result, exclusions, by_hand)
    if kept_in is None:
        return ()
    return beyond_noise(result.model.names, result.estimate, result.uncertainty.noise_std_error, kept_in,
                        ROBUST_CHOICE)


def robust_refit(result, exclusions, by_hand: np.ndarray) -> np.ndarray | None:
    """(p,) The reported estimate with the robust step's outside torques kept in, or None when the step found none
    (or the fit has no unique, unconstrained estimate with errors)."""
    uncertainty = result.uncertainty
    if (exclusions is None or exclusions.regressor is None or result.estimate is None or result.bounded is not None
            or uncertainty is None or uncertainty.noise_std_error is None):
        return None
    rows = ~exclusions.standstill & ~by_hand
    if np.array_equal(rows, exclusions.kept):  # the robust step found nothing: the same fit
        return None
    solution = solve_least_squares(exclusions.regressor[rows], exclusions.torque[rows])
    if solution.estimate is None:
        return None
    return result.model.report(solution.estimate)


def stretch_scatter(result, pieces: int = STRETCHES) -> tuple[Scatter, ...]:
    """Scatters of the fit's parameters over `pieces` contiguous stretches of its kept, filtered samples, each
    fitted alone; () when fewer than two stretches give a unique fit or the fit has no correlation grid."""
    if result.estimate is None or result.correlation is None or result.bounded is not None:
        return ()
    positions, lag = result.correlation
    X, tau, model = result.training_regressor, result.training.tau, result.model
    edges = np.linspace(positions[0], positions[-1] + 1, pieces + 1)
    # Each stretch must be far longer than the filter's support, or its pieces share their residuals.
    if edges[1] - edges[0] < 4 * lag:
        return ()
    values, errors = [], []
    for first, last in zip(edges[:-1], edges[1:]):
        inside = (positions >= first) & (positions < last)
        if inside.sum() <= 4 * X.shape[1]:
            continue
        fitted = _fit_rows(X[inside], tau[inside], positions[inside] - positions[inside][0], lag, model)
        if fitted is not None:
            values.append(fitted[0]), errors.append(fitted[1])
    if len(values) < 2:
        return ()
    ratios, significant = scatter_ratios(np.array(values), np.array(errors))
    word = {2: "halves", 3: "thirds"}.get(pieces, f"{pieces} stretches")
    return scatter_findings(model.names, ratios, significant, f"{word} of the run")


def _fit_rows(X: np.ndarray, tau: np.ndarray, positions: np.ndarray, lag: int, model
              ) -> tuple[np.ndarray, np.ndarray] | None:
    """(reported estimate, Newey-West standard errors) of rows fitted alone, or None without a unique fit."""
    solution = solve_least_squares(X, tau)
    if solution.estimate is None:
        return None
    with np.errstate(all="ignore"):
        correlated = newey_west(X, tau - X @ solution.estimate, positions, lag, covariance_factor(solution))
        uncertainty = parameter_uncertainty(solution, None, model, None, correlated)
    errors = uncertainty.noise_std_error
    if errors is None or not np.all(np.isfinite(errors)) or not np.all(errors > 0):
        return None
    return uncertainty.estimate, errors


def run_scatter(names, values: np.ndarray, errors: np.ndarray, pooled: np.ndarray) -> tuple[Scatter, ...]:
    """Scatters of several runs' own estimates (k, s) with standard errors about their pooled estimate (s,)."""
    if len(values) < 2:
        return ()
    ratios, significant = scatter_ratios(np.asarray(values, float), np.asarray(errors, float),
                                         np.asarray(pooled, float))
    return scatter_findings(names, ratios, significant, "runs")
