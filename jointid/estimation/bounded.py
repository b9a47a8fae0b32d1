"""Least squares subject to the model's sign rules (I >= a small floor, h, B, Fc >= 0).

A full-rank fit X D^-1 P = Q R reduces ||y - X theta||^2 to ||Q^T y - M theta||^2
plus a constant, with the small square M = R P^T D. With every column of full
rank the problem is strictly convex, so its one minimiser is the best of the
candidates "these bounds active, the rest free" that respect every bound: each
candidate is a small unconstrained solve, and with at most five bounded
parameters there are at most 32 of them. That is exact (no iteration, no
tolerance) and solves many right-hand sides at once, so a seed sweep can
constrain every seed. With no bound active the result is the unconstrained
estimate itself, bit for bit.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np

from ..model.terms import NONNEGATIVE, POSITIVE, JointModel
from .solver import LeastSquaresSolution

INERTIA_FLOOR = 1e-6
"""The bound a parameter that must be positive (the inertia, kg m²) is held at: 'greater than 0' as a number."""


def lower_bounds(model: JointModel) -> np.ndarray:
    """(p,) Lower bound of each column coefficient from its sign rule (-inf without one, or behind h and q0)."""
    bounds = np.full(model.size, -np.inf)
    for index, (parameter, term) in enumerate(zip(model.parameters, model.terms)):
        if parameter is term:  # an angle offset's h is a hypot, never negative: its columns stay free
            bounds[index] = {POSITIVE: INERTIA_FLOOR, NONNEGATIVE: 0.0}.get(parameter.sign, -np.inf)
    return bounds


def reduced_matrix(solution: LeastSquaresSolution) -> np.ndarray:
    """(p, p) M = R P^T D, so that ||y - X theta|| and ||Q^T y - M theta|| differ by a constant."""
    matrix = np.empty_like(solution.r_factor)
    matrix[:, solution.permutation] = solution.r_factor
    return matrix * solution.scales


@dataclass(frozen=True, eq=False)
class BoundedSolution:
    """The sign-constrained estimate of one or many right-hand sides."""

    estimate: np.ndarray
    """(p,) or (p, K) Column coefficients within their bounds."""
    active: np.ndarray
    """(p,) or (p, K) True where a coefficient is held at its bound."""
    residual_norm: float | np.ndarray
    """||y - X theta|| at the constrained estimate; (K,) for K right-hand sides."""


def bounded_least_squares(solution: LeastSquaresSolution, lower: np.ndarray) -> BoundedSolution:
    """Minimise ||y - X theta|| subject to theta >= lower, from a full-rank factorisation (one or K right-hand sides)."""
    if not solution.is_full_rank:
        raise ValueError("a bounded fit needs a full-rank regressor")
    single = solution.qty.ndim == 1
    qty = solution.qty[:, None] if single else solution.qty  # (p, K)
    free_fit = solution.estimate[:, None] if single else solution.estimate
    matrix = reduced_matrix(solution)
    count, seeds = matrix.shape[1], qty.shape[1]
    bounded = [j for j in range(count) if np.isfinite(lower[j])]
    best = np.array(free_fit, dtype=float)
    best_active = np.zeros((count, seeds), dtype=bool)
    best_value = np.where((free_fit >= lower[:, None]).all(axis=0), _objective(matrix, qty, free_fit), np.inf)
    for size in range(1, len(bounded) + 1):
        for held in combinations(bounded, size):
            free = [j for j in range(count) if j not in held]
            theta = np.empty((count, seeds))
            theta[list(held)] = lower[list(held), None]
            rhs = qty - matrix[:, list(held)] @ theta[list(held)]
            if free:
                theta[free] = np.linalg.lstsq(matrix[:, free], rhs, rcond=None)[0]
            feasible = (theta[free] >= lower[free, None]).all(axis=0) if free else np.ones(seeds, dtype=bool)
            value = np.where(feasible, _objective(matrix, qty, theta), np.inf)
            better = value < best_value  # strictly: a smaller active set wins a tie
            best[:, better], best_value[better] = theta[:, better], value[better]
            best_active[:, better] = False
            best_active[np.ix_(list(held), better.nonzero()[0])] = True
    residual = np.sqrt(best_value + np.square(solution.residual_norm))
    if single:
        return BoundedSolution(best[:, 0], best_active[:, 0], float(residual[0]))
    return BoundedSolution(best, best_active, residual)


def _objective(matrix: np.ndarray, qty: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """(K,) ||Q^T y - M theta||^2 per right-hand side."""
    return np.square(qty - matrix @ theta).sum(axis=0)
