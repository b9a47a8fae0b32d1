"""Do a fit's residuals follow a term its model lacks? A robust test for omitted terms, and what they would move.

A model that lacks an effect the joint has (friction, a torque bias, an angle
offset, drag growing with speed) leaves that effect in its residuals, and lets
the parameters whose columns resemble it absorb part of it. The test adds the
candidate columns Z to the fitted ones X and refits on the same filtered, kept
samples: a Wald test of Z's coefficients, with Newey-West (HAC) covariance
because filtered residuals are correlated, says whether the residuals follow Z;
each fitted parameter's move between the two fits, in its own standard error,
says which estimates the missing effect decides.

A whiteness or runs test of the residuals was tried first and kept out: on a
low-passed log the residuals are worth 20 to 40 independent samples, and such a
test missed a 0.2 N m Coulomb friction the model lacked (p 0.07 to 0.86 over six
seeds) that this test finds at p below 1e-10.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .solver import solve_least_squares
from .uncertainty import covariance_factor, newey_west_sum

LEVEL = 1e-3
"""Tail probability below which the residuals are said to follow the candidate terms."""
MOVE = 2.0
"""Standard errors a parameter must move when the terms are added for the missing effect to decide it."""


@dataclass(frozen=True)
class OmittedTerms:
    """The test of candidate terms against a fit's residuals, and each fitted column's move when they are added."""

    candidates: tuple[str, ...]
    """The candidate terms' names, as the model ladder and jointid's reports spell them."""
    statistic: float
    """The Wald statistic of the candidates' coefficients (chi-squared with len(candidates) degrees of freedom)."""
    p_value: float
    each_p_value: tuple[float, ...]
    """Each candidate's own Wald tail probability (one degree of freedom)."""
    columns: tuple[str, ...]
    """The fitted model's column names."""
    moves: tuple[float, ...]
    """Each fitted column's move when the candidates are added, in its own (HAC) standard errors."""

    @property
    def found(self) -> bool:
        """True when the residuals follow the candidate terms (p below LEVEL)."""
        return self.p_value < LEVEL

    @property
    def followed(self) -> tuple[str, ...]:
        """The candidates that each pass the test on their own (or, when none does alone, all of them)."""
        alone = tuple(name for name, p in zip(self.candidates, self.each_p_value) if p < LEVEL)
        return alone or self.candidates

    @property
    def decided(self) -> tuple[str, ...]:
        """The fitted columns the missing terms move by more than MOVE standard errors (none unless `found`)."""
        if not self.found:
            return ()
        return tuple(name for name, move in zip(self.columns, self.moves) if move > MOVE)


def chi_squared_tail(statistic: float, dof: int) -> float:
    """P(chi-squared with `dof` degrees of freedom > statistic), in closed form for whole degrees of freedom."""
    half = max(statistic, 0.0) / 2
    if dof % 2 == 0:  # a Poisson sum
        term = total = 1.0
        for i in range(1, dof // 2):
            term *= half / i
            total += term
        return min(1.0, math.exp(-half) * total)
    # odd: erfc, then the half-integer terms
    total = math.erfc(math.sqrt(half))
    term = math.sqrt(half / math.pi) * 2 * math.exp(-half) if dof > 1 else 0.0
    for i in range(1, (dof - 1) // 2 + 1):
        if i > 1:
            term *= half / (i - 0.5)
        total += term
    return min(1.0, total)


def omitted_terms_test(X: np.ndarray, Z: np.ndarray, tau: np.ndarray, positions: np.ndarray, lag: int,
                       columns: tuple[str, ...], candidates: tuple[str, ...]) -> OmittedTerms | None:
    """Test the candidate columns Z (n, k) against the fit of tau (n,) on X (n, p), with HAC errors over `lag`
    steps of the grid the samples sit at (`positions`); None when either fit is not unique."""
    p, k = X.shape[1], Z.shape[1]
    base = solve_least_squares(X, tau)
    W = np.column_stack([X, Z])
    wide = solve_least_squares(W, tau)
    if base.estimate is None or wide.estimate is None or k == 0:
        return None
    factor = covariance_factor(base)
    meat, _ = newey_west_sum(X, tau - X @ base.estimate, positions, lag)
    base_errors = np.sqrt(np.maximum(np.diag(factor @ meat @ factor), 0.0))
    wide_factor = covariance_factor(wide)
    wide_meat, _ = newey_west_sum(W, tau - W @ wide.estimate, positions, lag)
    covariance = (wide_factor @ wide_meat @ wide_factor)[p:, p:]
    gamma = wide.estimate[p:]
    try:
        statistic = float(gamma @ np.linalg.solve(covariance, gamma))
    except np.linalg.LinAlgError:
        return None
    each = tuple(chi_squared_tail(float(g * g / c), 1) if c > 0 else 1.0 for g, c in zip(gamma, np.diag(covariance)))
    with np.errstate(divide="ignore", invalid="ignore"):
        moves = np.abs(wide.estimate[:p] - base.estimate) / base_errors
    moves = np.where(np.isfinite(moves), moves, 0.0)
    if not (math.isfinite(statistic) and np.all(np.isfinite(gamma))):
        return None
    return OmittedTerms(tuple(candidates), statistic, chi_squared_tail(statistic, k), each, tuple(columns),
                        tuple(float(m) for m in moves))
