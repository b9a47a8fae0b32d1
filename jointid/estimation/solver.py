"""Column-scaled, column-pivoted Householder least squares with a rank check, by row blocks.

min ||y - X theta|| for X of shape (N, p) is solved in two stages.

Reduction. Above `DIRECT_ROWS` rows, [X | y] is cut into blocks of rows
(`block_rows_for`) and read a group of blocks at a time (a TSQR): one call of
LAPACK's Householder QR batched over the group (numpy's gufunc behind
numpy.linalg.qr, see `_factor_in_place`) triangularises each block, and a
second call factors those triangles, stacked under the
triangle of all earlier rows, into the triangle of all rows so far. Of that
(p + 1, p + 1) triangle the first p columns are R and the last holds Q^T y and,
below it, the residual norm of the rows so far, which LAPACK accumulates
without overflow. Only the triangle is kept: X is never copied whole and the
temporaries are about one group in size. Up to `DIRECT_ROWS` rows the second
stage works on X itself, exactly as before the reduction existed.

Rank-revealing step. Each nonzero column of R (or X) is scaled to unit norm,
then Householder reflections triangularise the scaled matrix, choosing at
every step the remaining column with the largest norm, recomputed exactly. When
that norm is at most `RANK_TOLERANCE` the remaining columns are numerically
dependent and the rank stops there. Only a full-rank problem gets an estimate;
X^T X is never formed. The residual norm combines what this step leaves of
Q^T y past the rank with the reduction's residual norm.

Why pivoting R is pivoting X: X = Q R with Q's columns orthonormal, and Q keeps
lengths and angles, so the distance of any column of X from the span of any
other columns equals that of the same column of R. The column norms (hence the
scales, computed from R) and every remaining norm the pivoting compares are
such distances: in exact arithmetic R and X give the same pivots, the same
rank, the same triangular factor up to row signs, and the same estimates and
residual. In floating point they differ by the factorisations' backward error,
which for Householder QR is small column by column, relative to each column's
norm; that is also why X can be factored unscaled and R's columns scaled
afterwards, saving a pass over the data.

Many right-hand sides: in the rank-revealing step they are reflected with
numpy row sums, never BLAS, whose kernels for one dot product and for many add
in different orders. In the reduction each column of y gets its own LAPACK
factorisation, of the same shapes as a lone y's: X's part is refactored K
times, which at K = 4 to 200 takes 1.3-1.8x as long as reflecting the K
columns in numpy would, but a lone y, the common case, 0.7x. Either way
column k of a K-column solve equals, bit for bit, the solve of y[:, k] alone,
which the seed sweep relies on.

Inputs must be finite, and a full-rank estimate is checked to be finite: a
NaN compares false with the rank tolerance, so unchecked it would pass for a
full-rank column and give a "unique fit" of NaNs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..checks import checked, optional, real, real_array, whole
from ..norms import column_norms, row_norms

try:  # the gufunc numpy.linalg.qr(mode="raw") calls on a copy of its argument
    from numpy.linalg._umath_linalg import qr_r_raw as _lapack_qr_in_place
except ImportError:  # another numpy's layout: numpy.linalg.qr itself, and its copy
    _lapack_qr_in_place = None

RANK_TOLERANCE = 1e-10
"""A remaining scaled column norm at or below this is numerically dependent."""
DIRECT_ROWS = 8192
"""Up to this many rows X is triangularised whole by the rank-revealing step; above, it is reduced first."""
BLOCK_VALUES = 8192
"""Values of X in one block of the reduction (see `block_rows_for`)."""
GROUP_VALUES = 2**16
"""Values of [X | y] in one group of blocks, factored by one call of numpy's (batched) QR: 512 kB."""

PRODUCT_PIECE = 1 << 17
"""Multiply-adds per piece of a long matrix product: OpenBLAS runs products below 2^18 on one thread, which on a
busy 2-core machine is faster than waking its threads (the filter's, the robust step's and Newey-West's)."""


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


@checked(X=real_array(finite=False), y=real_array(finite=False), tolerance=real(0.0), block_rows=optional(whole(1)))
def solve_least_squares(
    X, y, tolerance: float = RANK_TOLERANCE, *, block_rows: int | None = None
) -> LeastSquaresSolution:
    """Factor column-scaled X (N, p) with pivoted Householder QR and solve for y (N,) or (N, K).

    With K right-hand sides (one column of y each) the one factorisation serves
    them all: `qty` becomes (rank, K), `residual_norm` (K,), and the estimates
    (p, K). Column k of a multi-RHS solve equals, bit for bit, the solve of y[:, k]
    alone. Inputs are not modified. N may be smaller than p, and p may be zero.
    Above `DIRECT_ROWS` rows, X is first reduced to a triangle in blocks of
    `block_rows_for(p)` rows; an explicit `block_rows` reduces any X taller than
    one block (tests use it to reach the blocked path with small problems).
    NonFiniteError if X or y is not finite, or if a full-rank estimate overflows.

    Parameters
    ----------
    X : array_like
        (N, p) regressor.
    y : array_like
        (N,) or (N, K) targets.
    tolerance : float
        A remaining column norm at or below this, after unit-column scaling, counts as dependent (1e-10).

    Returns
    -------
    LeastSquaresSolution
        The rank, the estimate (None below full rank), residual norms and the factorisation.
    """
    X = np.asarray(X, dtype=float)
    y = np.asarray(y, dtype=float)
    if X.ndim != 2 or y.ndim not in (1, 2) or y.shape[0] != X.shape[0]:
        raise ValueError(f"X must be (N, p) and y (N,) or (N, K); got {X.shape} and {y.shape}")
    for name, values in (("the regressor X", X), ("the observations y", y)):
        # One pass: a finite sum has no NaN or infinity in it (both propagate). Only a sum that overflows
        # needs the second look, min and max, which reach any infinity without an (N, p) temporary.
        with np.errstate(over="ignore", invalid="ignore"):  # the command line's strict arithmetic would raise
            total = values.sum()
        if values.size and not math.isfinite(total) and not (
            math.isfinite(values.min()) and math.isfinite(values.max())
        ):
            raise NonFiniteError(f"{name} holds values that are not finite numbers")
    rows, columns = X.shape
    if block_rows is None:
        reduce = rows > DIRECT_ROWS
        block_rows = block_rows_for(columns)
    elif block_rows >= 1:
        reduce = rows > block_rows
    else:
        raise ValueError(f"block_rows must be at least 1; got {block_rows}")
    if reduce and columns:
        # The same least-squares problem in min(N, p) rows: R theta ~ Q^T y, plus the
        # residual of the rows reduced away.
        triangle, targets, reduced_residual = _reduce_by_blocks(X, y, block_rows)
    else:
        triangle, reduced_residual = X, 0.0
        # Right-hand sides as contiguous rows (K, N), one per y column: a single y is
        # the K = 1 case of the same code, which is what makes many solves match one.
        targets = np.array(y.T if y.ndim == 2 else y[None, :], order="C")
    # Overflow-safe: a column of 1e200s has a norm, not an infinite one that would scale it to zero.
    norms = column_norms(triangle)
    scales = np.where(norms > 0, norms, 1.0)
    # A scaled copy in column-major order, so each column operation is contiguous.
    work = np.empty(triangle.shape, order="F")
    np.divide(triangle, scales, out=work)
    rank, permutation = _pivoted_householder(work, targets, tolerance)
    # hypot: no overflow, and x exactly when the reduction left no residual (small N).
    residual_norms = np.hypot(row_norms(targets[:, rank:]), reduced_residual)
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


def block_rows_for(columns: int, values: int = BLOCK_VALUES) -> int:
    """Rows per block of the reduction for p = `columns`: `values` (`BLOCK_VALUES`) // p.

    A block's part of X then holds at most `values` numbers, so the
    matrix-vector steps inside LAPACK's QR of the block stay below OpenBLAS's
    thresholds for starting threads (8192 for dger, 9216 for dgemv): those
    threads cost far more than they save on a shared machine (above them,
    6-column solves ran 5 to 20x slower under load), and the block stays in the
    core's own cache. The largest such block was the fastest measured. From 91
    columns on, no block fits; blocks then keep p + 1 rows.
    """
    return max(columns + 1, values // max(columns, 1))


def triangle_of(X: np.ndarray, y: np.ndarray, direct_rows: int = DIRECT_ROWS) -> np.ndarray:
    """(n, p + 1) upper triangle T of [X | y] (N, p) and (N,), n = min(N, p + 1): for every theta,
    ||y - X theta|| = ||T[:, p] - T[:, :p] theta||, so any subset of X's columns can be fitted from T alone.

    One blocked pass above `direct_rows` rows (as `solve_least_squares` reduces X), LAPACK's QR below.
    """
    X, y = np.asarray(X, dtype=float), np.asarray(y, dtype=float)
    rows, columns = X.shape
    if rows <= direct_rows:
        return np.linalg.qr(np.column_stack([X, y]), mode="r")
    r_factor, qty, residual = _reduce_by_blocks(X, y, block_rows_for(columns))
    triangle = np.zeros((min(rows, columns + 1), columns + 1))
    triangle[:columns, :columns], triangle[:columns, columns] = r_factor, qty[0]
    if rows > columns:
        triangle[columns, columns] = residual[0]
    return triangle


def _reduce_by_blocks(X: np.ndarray, y: np.ndarray, block_rows: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(R (n, p), Q^T y (K, n), residual norms (K,)) of X (N, p) and y (N,) or (N, K), n = min(N, p), by row blocks."""
    rows, columns = X.shape
    width = columns + 1
    count = 1 if y.ndim == 1 else y.shape[1]
    # With no right-hand side at all, a zero one (a view, no memory) carries R through.
    Y = y[:, None] if y.ndim == 1 else y if count else np.broadcast_to(np.zeros(1), (rows, 1))
    group = max(1, GROUP_VALUES // (block_rows * width))
    upper = np.triu(np.ones((width, width), dtype=bool))
    # Per right-hand side, the triangle of [X | y_k] so far, min(rows so far, p + 1) rows:
    # its first p columns, R, are the same for every k; its last column holds Q^T y_k
    # and then the residual norm.
    triangles = [np.zeros((0, width))] * Y.shape[1]
    # A group of blocks, each column-major for LAPACK: (group, block_rows, p + 1).
    buffer = np.empty((group, width, block_rows)).transpose(0, 2, 1)
    for start in range(0, rows, group * block_rows):
        full = min(group, (rows - start) // block_rows)
        middle = start + full * block_rows
        rest = slice(middle, min(start + group * block_rows, rows))
        blocks = buffer[:full]
        for k in range(len(triangles)):
            # Each right-hand side in its own factorisations, of the same shapes as a lone
            # y's, so that its numbers never depend on the other columns of y (X's part is
            # copied again for each: the factorisation overwrites it).
            blocks[:, :, :columns] = X[start:middle].reshape(full, block_rows, columns)
            blocks[:, :, columns] = Y[start:middle, k].reshape(full, block_rows)
            pieces = [triangles[k]]
            if full:
                pieces.append(_triangles(_factor_in_place(blocks), upper).reshape(-1, width))
            if rest.start < rest.stop:
                pieces.append(np.column_stack([X[rest], Y[rest, k]]))
            # The triangles of the group's blocks, stacked under the one so far (and the
            # rows too few to make a block), factored into the triangle of all rows so far.
            triangles[k] = _triangles(_factor_in_place(np.concatenate(pieces)), upper)
    kept = min(rows, columns)
    last = np.empty((count, len(triangles[0])))
    for k in range(count):
        last[k] = triangles[k][:, columns]
    residual = np.abs(last[:, kept]) if rows > columns else np.zeros(count)
    return triangles[0][:kept, :columns], np.array(last[:, :kept], order="C"), residual


def _factor_in_place(matrices: np.ndarray) -> np.ndarray:
    """`matrices` (..., m, p + 1), each overwritten by LAPACK's Householder QR (dgeqrf) of it: R on and above
    the diagonal, the reflectors below.

    numpy.linalg.qr(mode="raw") computes the same on a copy and hands back its transpose; the matrices here
    are the reduction's own scratch, so where numpy's gufunc can be imported they are factored where they
    lie (one copy of every group fewer), with the same bits.
    """
    if _lapack_qr_in_place is None:
        matrices[...] = np.swapaxes(np.linalg.qr(matrices, mode="raw")[0], -1, -2)
    else:
        _lapack_qr_in_place(matrices, signature="d->d")
    return matrices


def _triangles(factored: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """The upper triangles (..., min(m, p + 1), p + 1) of matrices (..., m, p + 1) factored in place."""
    kept = min(factored.shape[-2], factored.shape[-1])
    return np.where(upper[:kept], factored[..., :kept, :], 0.0)  # the reflectors below the diagonal become 0


def _pivoted_householder(work: np.ndarray, targets: np.ndarray, tolerance: float) -> tuple[int, np.ndarray]:
    """Pivoted Householder QR of `work` (M, p) in place, reflecting `targets` (K, M) alike; (rank, permutation)."""
    rows, columns = work.shape
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
    return rank, permutation


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
