"""Column-scaled, column-pivoted Householder least squares with a rank check.

Each nonzero column is scaled to unit Euclidean norm, then Householder
reflections triangularise the scaled matrix, choosing at every step the
remaining column with the largest norm. When that norm is at most
`RANK_TOLERANCE` the remaining columns are numerically dependent and the rank
stops there. Only a full-rank problem gets an estimate; X^T X is never formed
and memory stays O(N*p).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

RANK_TOLERANCE = 1e-10
"""A remaining scaled column norm at or below this is numerically dependent."""


@dataclass(frozen=True, eq=False)
class LeastSquaresSolution:
    """The factorisation and solution of min ||y - X theta|| for X of shape (N, p)."""

    rank: int
    """Numerical rank found by the pivoted factorisation."""
    column_count: int
    """p, the number of parameters."""
    row_count: int
    """N, the number of observations."""
    scales: np.ndarray
    """(p,) Column norms used for scaling (1 for zero columns)."""
    permutation: np.ndarray
    """(p,) Original column index of each pivoted position."""
    r_factor: np.ndarray
    """(rank, p) Upper-trapezoidal R of the scaled, pivoted matrix."""
    qty: np.ndarray
    """(rank,) First `rank` entries of Q^T y."""
    residual_norm: float
    """||y - X theta|| at any least-squares solution."""

    @property
    def is_full_rank(self) -> bool:
        """True when rank equals the number of columns, so the solution is unique."""
        return self.rank == self.column_count

    @cached_property
    def estimate(self) -> np.ndarray | None:
        """(p,) The unique least-squares theta, or None when the rank is deficient."""
        if not self.is_full_rank:
            return None
        scaled = back_substitute(self.r_factor, self.qty)
        theta = np.empty(self.column_count)
        theta[self.permutation] = scaled
        return theta / self.scales

    @cached_property
    def basic_estimate(self) -> np.ndarray:
        """(p,) A least-squares theta with the dependent (non-pivot) columns set to zero."""
        rank = self.rank
        scaled = np.zeros(self.column_count)
        scaled[:rank] = back_substitute(self.r_factor[:, :rank], self.qty)
        theta = np.empty(self.column_count)
        theta[self.permutation] = scaled
        return theta / self.scales


def back_substitute(upper: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Solve upper @ x = rhs for square upper-triangular `upper` of shape (p, p)."""
    size = len(rhs)
    x = np.zeros(size)
    for i in range(size - 1, -1, -1):
        x[i] = (rhs[i] - upper[i, i + 1 :] @ x[i + 1 :]) / upper[i, i]
    return x


def solve_least_squares(X, y, tolerance: float = RANK_TOLERANCE) -> LeastSquaresSolution:
    """Factor column-scaled X (N, p) with pivoted Householder QR and solve for y (N,).

    Inputs are not modified. N may be smaller than p, and p may be zero.
    """
    X = np.asarray(X, dtype=float)
    y = np.asarray(y, dtype=float)
    if X.ndim != 2 or y.shape != (X.shape[0],):
        raise ValueError(f"X must be (N, p) and y (N,); got {X.shape} and {y.shape}")
    rows, columns = X.shape
    norms = np.sqrt(np.einsum("ij,ij->j", X, X))
    scales = np.where(norms > 0, norms, 1.0)
    # A scaled copy in column-major order, so each column operation is contiguous.
    work = np.empty((rows, columns), order="F")
    np.divide(X, scales, out=work)
    rhs = y.copy()
    permutation = np.arange(columns)
    rank = 0
    for k in range(min(rows, columns)):
        trailing = work[k:, k:]
        # Recompute remaining norms exactly each step (cheap for small p) instead of
        # down-dating them, which loses accuracy after cancellation.
        remaining = np.sqrt(np.einsum("ij,ij->j", trailing, trailing))
        pivot = k + int(np.argmax(remaining))
        if remaining[pivot - k] <= tolerance:
            break
        if pivot != k:
            work[:, [k, pivot]] = work[:, [pivot, k]]
            permutation[[k, pivot]] = permutation[[pivot, k]]
        _reflect(work, rhs, k, remaining[pivot - k])
        rank += 1
    residual_norm = float(np.linalg.norm(rhs[rank:]))
    return LeastSquaresSolution(
        rank=rank,
        column_count=columns,
        row_count=rows,
        scales=scales,
        permutation=permutation,
        r_factor=np.triu(work[:rank, :]),
        qty=rhs[:rank].copy(),
        residual_norm=residual_norm,
    )


def _reflect(work: np.ndarray, rhs: np.ndarray, k: int, column_norm: float) -> None:
    """Apply the Householder reflection that zeros work[k+1:, k] to work[k:, k:] and rhs[k:]."""
    head = work[k, k]
    alpha = -column_norm if head >= 0 else column_norm
    v = work[k:, k].copy()
    v[0] -= alpha
    v /= np.linalg.norm(v)
    # Column by column: no (N, p) temporary, and each update is one contiguous axpy.
    for column in [work[k:, j] for j in range(k + 1, work.shape[1])] + [rhs[k:]]:
        column -= (2.0 * (v @ column)) * v
    work[k:, k] = 0.0
    work[k, k] = alpha
