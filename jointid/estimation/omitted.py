"""Do a fit's residuals follow a term its model lacks? A robust test for omitted terms, and what they would move.

A model that lacks an effect the joint has (friction, a torque bias, an angle
offset, drag growing with speed) leaves that effect in its residuals, and lets
the parameters whose columns resemble it absorb part of it. Each candidate
column z is added alone to the fitted columns X and the same filtered, kept
samples are refitted: z's coefficient over its Newey-West (HAC) standard error
is a t statistic, judged against Student's t with the residuals' effective
number of independent samples (filtered residuals are correlated: a log of
thousands of samples may be worth a few dozen), at LEVEL shared by the
candidates (Bonferroni). Each fitted parameter's move between the two fits, in
its own standard error, says whether the missing term matters at the precision
claimed: a parameter is decided by a missing term when a term the residuals
follow moves it by more than MOVE of them.

A whiteness or runs test of the residuals was tried first and kept out: on a
low-passed log the residuals are worth a few dozen independent samples, and
such a test missed a 0.2 N m Coulomb friction the model lacked (p 0.07 to 0.86
over six seeds). All candidates tested together with the chi-squared
approximation rejected a right model on 4 of 8 quantised synthetic logs; one at
a time, on the effective count and at LEVEL, none of 20 (benchmarks/omitted_terms_study.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .solver import solve_least_squares
from .student_t import student_t_quantile
from .uncertainty import covariance_factor, newey_west_sum

LEVEL = 1e-4
"""Nominal chance, for a right model, that any candidate is said to be followed (shared by the candidates).
Nominal: on quantised logs the residuals also carry the derivatives' errors, and a right model's |t| reached 4.4
in 80 tries (benchmarks/omitted_terms_study.py), past the 0.1 % level; at this level none passed."""
MOVE = 2.0
"""A parameter must move more than this many of its own standard errors for the missing term to decide it."""


@dataclass(frozen=True)
class CandidateTest:
    """One candidate term added alone: its t statistic, and each fitted column's move."""

    name: str
    """The term's name, as the model ladder and jointid's reports spell it ('Fc', 'tau0', 'h_s', 'Bq')."""
    t: float
    """Its coefficient over its HAC standard error."""
    moves: tuple[float, ...]
    """Each fitted column's move when it is added, in that column's own (HAC) standard errors."""


@dataclass(frozen=True)
class OmittedTerms:
    """The candidates' tests, the threshold they are judged against, and which fitted columns they decide."""

    candidates: tuple[CandidateTest, ...]
    columns: tuple[str, ...]
    """The fitted model's column names, in the order of each candidate's moves."""
    effective_count: float
    """How many independent samples the fit's residuals are worth."""
    threshold: float
    """|t| beyond which a candidate is followed: Student's t at LEVEL / (2 x candidates), effective count less p + 1."""

    @property
    def followed(self) -> tuple[str, ...]:
        """The candidates whose |t| passes the threshold."""
        return tuple(test.name for test in self.candidates if abs(test.t) > self.threshold)

    @property
    def found(self) -> bool:
        """True when the residuals follow at least one candidate."""
        return bool(self.followed)

    @property
    def decided(self) -> tuple[str, ...]:
        """The fitted columns a followed candidate moves by more than MOVE of their own standard errors."""
        decided = set()
        for test in self.candidates:
            if abs(test.t) > self.threshold:
                decided |= {name for name, move in zip(self.columns, test.moves) if move > MOVE}
        return tuple(name for name in self.columns if name in decided)


def hac_fit(X: np.ndarray, tau: np.ndarray, positions: np.ndarray, lag: int):
    """(estimate, HAC covariance, effective count) of the least-squares fit of tau on X, or None without a unique
    fit."""
    solution = solve_least_squares(X, tau)
    if solution.estimate is None:
        return None
    factor = covariance_factor(solution)
    meat, autocorrelation = newey_west_sum(X, tau - X @ solution.estimate, positions, lag)
    return solution.estimate, factor @ meat @ factor, len(tau) / autocorrelation


def omitted_terms_test(X: np.ndarray, Z: np.ndarray, tau: np.ndarray, positions: np.ndarray, lag: int,
                       columns: tuple[str, ...], candidates: tuple[str, ...]) -> OmittedTerms | None:
    """Test each candidate column of Z (n, k) against the fit of tau (n,) on X (n, p), with HAC errors over `lag`
    steps of the grid the samples sit at (`positions`); None when the fit is not unique or has no samples to
    spare."""
    base = hac_fit(X, tau, positions, lag)
    p, k = X.shape[1], Z.shape[1]
    if base is None or k == 0:
        return None
    estimate, covariance, effective = base
    degrees = effective - p - 1
    if not degrees >= 1:
        return None
    own = np.sqrt(np.maximum(np.diag(covariance), 0.0))
    tests = []
    for j, name in enumerate(candidates):
        wide = hac_fit(np.column_stack([X, Z[:, j]]), tau, positions, lag)
        if wide is None:
            continue
        wide_estimate, wide_covariance, _ = wide
        error = float(np.sqrt(max(wide_covariance[p, p], 0.0)))
        if not (error > 0 and np.all(np.isfinite(wide_estimate))):
            continue
        with np.errstate(divide="ignore", invalid="ignore"):
            moves = np.abs(wide_estimate[:p] - estimate) / own
        tests.append(CandidateTest(name, float(wide_estimate[p]) / error,
                                   tuple(float(m) if np.isfinite(m) else 0.0 for m in moves)))
    if not tests:
        return None
    threshold = student_t_quantile(1 - LEVEL / (2 * len(tests)), degrees)
    return OmittedTerms(tuple(tests), tuple(columns), float(effective), float(threshold))
