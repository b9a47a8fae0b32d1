"""Column-scaled, column-pivoted Householder least squares with a rank check.

Each nonzero column is scaled to unit Euclidean norm, then Householder
reflections triangularise the scaled matrix, choosing at every step the
remaining column with the largest norm. When that norm is at most
`RANK_TOLERANCE` the remaining columns are numerically dependent and the rank
stops there. Only a full-rank problem gets an estimate; X^T X is never formed
and memory stays O(N*p).

Inputs must be finite, and a full-rank estimate is checked to be finite: a
NaN compares false with the rank tolerance, so unchecked it would pass for a
full-rank column and give a "unique fit" of NaNs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .norms import column_norms, row_norms

RANK_TOLERANCE = 1e-10
"""A remaining scaled column norm at or below this is numerically dependent."""


class NonFiniteError(ValueError):
    """X or y holds infinity or NaN, or the estimate overflows double precision; one line for a user."""


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
    """(rank,) First `rank` entries of Q^T y; (rank, K) for K right-hand sides."""
    residual_norm: float | np.ndarray
    """||y - X theta|| at any least-squares solution; (K,) for K right-hand sides."""

    @property
    def is_full_rank(self) -> bool:
        """True when rank equals the number of columns, so the solution is unique."""
        return self.rank == self.column_count

    @cached_property
    def estimate(self) -> np.ndarray | None:
        """(p,) The unique least-squares theta ((p, K) for K right-hand sides), or None when rank-deficient."""
        if not self.is_full_rank:
            return None
        return self._unscale(back_substitute(self.r_factor, self.qty))

    @cached_property
    def basic_estimate(self) -> np.ndarray:
        """(p,) A least-squares theta ((p, K) for K right-hand sides) with the non-pivot columns set to zero."""
        rank = self.rank
        scaled = np.zeros((self.column_count,) + self.qty.shape[1:])
        scaled[:rank] = back_substitute(self.r_factor[:, :rank], self.qty)
        return self._unscale(scaled)

    def _unscale(self, scaled: np.ndarray) -> np.ndarray:
        """Undo the pivoting and the column scaling of a (p,) or (p, K) solution."""
        theta = np.empty(scaled.shape)
        theta[self.permutation] = scaled
        return theta / self.scales.reshape((-1,) + (1,) * (scaled.ndim - 1))

    @cached_property
    def singular_values(self) -> np.ndarray:
        """(min(N, p),) Singular values of the column-scaled regressor, largest first (zeros past the rank)."""
        values = np.zeros(min(self.row_count, self.column_count))
        if self.rank:
            values[: self.rank] = np.linalg.svd(self.r_factor, compute_uv=False)
        return values

    @cached_property
    def condition_number(self) -> float:
        """Largest over smallest singular value of the column-scaled regressor (inf when rank-deficient)."""
        if not self.is_full_rank or self.column_count == 0:
            return math.inf
        return float(self.singular_values[0] / self.singular_values[-1])


def back_substitute(upper: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Solve upper @ x = rhs for square upper-triangular `upper` (p, p) and rhs (p,) or (p, K)."""
    rhs = np.asarray(rhs, dtype=float)
    x = np.zeros(rhs.shape)
    for i in range(len(rhs) - 1, -1, -1):
        # Terms added one by one in a fixed order, so every right-hand side, alone or
        # among many, gets bit-for-bit the same answer.
        total = np.zeros(rhs.shape[1:])
        for j in range(i + 1, len(rhs)):
            total = total + upper[i, j] * x[j]
        x[i] = (rhs[i] - total) / upper[i, i]
    return x


def solve_least_squares(X, y, tolerance: float = RANK_TOLERANCE) -> LeastSquaresSolution:
    """Factor column-scaled X (N, p) with pivoted Householder QR and solve for y (N,) or (N, K).

    With K right-hand sides (one column of y each) the one factorisation serves
    them all: `qty` becomes (rank, K), `residual_norm` (K,), and the estimates
    (p, K). Column k of a multi-RHS solve equals, bit for bit, the solve of y[:, k]
    alone. Inputs are not modified. N may be smaller than p, and p may be zero.
    NonFiniteError if X or y is not finite, or if a full-rank estimate overflows.
    """
    X = np.asarray(X, dtype=float)
    y = np.asarray(y, dtype=float)
    if X.ndim != 2 or y.ndim not in (1, 2) or y.shape[0] != X.shape[0]:
        raise ValueError(f"X must be (N, p) and y (N,) or (N, K); got {X.shape} and {y.shape}")
    for name, values in (("the regressor X", X), ("the observations y", y)):
        # min and max propagate NaN and reach any infinity, without an (N, p) temporary.
        if values.size and not (math.isfinite(values.min()) and math.isfinite(values.max())):
            raise NonFiniteError(f"{name} holds values that are not finite numbers")
    rows, columns = X.shape
    # Overflow-safe: a column of 1e200s has a norm, not an infinite one that would scale it to zero.
    norms = column_norms(X)
    scales = np.where(norms > 0, norms, 1.0)
    # A scaled copy in column-major order, so each column operation is contiguous.
    work = np.empty((rows, columns), order="F")
    np.divide(X, scales, out=work)
    # Right-hand sides as contiguous rows (K, N), one per y column: a single y is
    # the K = 1 case of the same code, which is what makes many solves match one.
    targets = np.array(y.T if y.ndim == 2 else y[None, :], order="C")
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
        _reflect(work, targets, k, remaining[pivot - k])
        rank += 1
    residual_norms = row_norms(targets[:, rank:])
    qty = np.array(targets[:, :rank].T, order="C")
    solution = LeastSquaresSolution(
        rank=rank,
        column_count=columns,
        row_count=rows,
        scales=scales,
        permutation=permutation,
        r_factor=np.triu(work[:rank, :]),
        qty=qty if y.ndim == 2 else qty[:, 0],
        residual_norm=residual_norms if y.ndim == 2 else float(residual_norms[0]),
    )
    if solution.is_full_rank:
        with np.errstate(over="ignore", invalid="ignore"):  # checked at once, with a message
            estimate = solution.estimate
        if not np.isfinite(estimate).all():
            raise NonFiniteError("the estimate overflows double precision: the columns differ in scale by too much")
    return solution


def _reflect(work: np.ndarray, targets: np.ndarray, k: int, column_norm: float) -> None:
    """Apply the reflection that zeros work[k+1:, k] to work[k:, k:] and to every row of targets[:, k:]."""
    head = work[k, k]
    alpha = -column_norm if head >= 0 else column_norm
    v = work[k:, k].copy()
    v[0] -= alpha
    v /= np.linalg.norm(v)
    # Column by column: no (N, p) temporary, and each update is one contiguous axpy.
    for j in range(k + 1, work.shape[1]):
        column = work[k:, j]
        column -= (2.0 * (v @ column)) * v
    # Right-hand sides: row sums along the contiguous axis (numpy's pairwise sum, the
    # same for one row or many) rather than BLAS, whose kernels for one dot product
    # and for a matrix-vector product add in different orders.
    tails = targets[:, k:]
    tails -= (2.0 * (tails * v).sum(axis=1))[:, None] * v
    work[k:, k] = 0.0
    work[k, k] = alpha
