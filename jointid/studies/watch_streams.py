"""The log pipeline's filters and least-squares statistics, applied to samples as they arrive (a live source).

Each stage keeps only the tail of its input that later outputs still need, so memory and the work per sample do not
grow with the time watched:

- `DerivativeStream`: the regressor columns and effort of a joint model at full rate, with qd and qdd estimated
  from q as jointid.logs.derivatives does (Savitzky-Golay smoothing, central differences) and every column not
  made from the derivatives smoothed alike; an output waits until its whole window has arrived, so it equals the
  offline value away from the ends (whose end polynomials a stream cannot know);
- `LowPassStream`: the parallel low-pass and decimation of jointid.estimation.low_pass, evaluated at the kept rows
  once the filter's whole window has arrived (the offline filter's value there, to rounding);
- `BatchStatistics`: the upper triangle of [X | y] of every row so far (its QR update), and the same for contiguous
  batches of rows, merged pairwise so their number stays bounded: the estimate and its covariance factor come from
  the whole triangle, and each batch may keep its Newey-West sums at one lag (LaggedSums), so any run of batches
  (a half, for the halves' scatter) has its own estimate and Newey-West errors, as a log fit's stretch has;
- `NeweyWestSums`: the lagged fourth-order sums from which a log fit's Newey-West covariance of every row so far
  follows for any estimate, in memory bounded by the longest lag.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..logs.derivatives import ROUNDING_FLOOR, savgol_coefficients
from ..estimation.low_pass import ParallelFilter
from ..estimation.solver import LeastSquaresSolution, solve_least_squares
from ..estimation.uncertainty import covariance_factor

MAX_BATCHES = 64
"""Batches kept before adjacent pairs are merged (to half as many, each twice as long)."""


class DerivativeStream:
    """A model's regressor columns and the effort at full rate, from blocks of raw samples (one segment: no gap)."""

    def __init__(self, terms, step: float, window: int | None, order: int):
        """`window` None: qd and qdd are given with q (nothing to estimate or smooth)."""
        self.terms, self.step, self.window, self.order = tuple(terms), step, window, order
        self.half = 0 if window is None else window // 2
        # Outputs at [a, b) need q from a - reach: smoothing q (half), two central differences, then the columns'
        # own smoothing (half), which may read the estimated speed (Coulomb's sign qd).
        self.reach = 0 if window is None else 2 * self.half + 2
        self.weights = None if window is None else savgol_coefficients(window, order, 0)
        self._raw: dict[str, np.ndarray] = {}
        self._start = 0
        """Segment index of the buffer's first sample."""
        self.emitted = 0 if window is None else self.reach
        """Segment index of the next output (the first `reach` samples have no whole window)."""
        self._largest = 0.0

    @property
    def size(self) -> int:
        """Numbers its buffer holds."""
        return _held(self._raw)

    def add(self, columns: dict[str, np.ndarray]) -> dict[str, np.ndarray] | None:
        """Append raw columns (q, tau, qd and qdd when given, t); return the outputs now complete: 'X' (n, p),
        'tau', 'q', 'qd', 'qdd', 't' (n,), and 'index' (n,) their positions in the segment; None when none is."""
        for name, values in columns.items():
            old = self._raw.get(name)
            self._raw[name] = values if old is None else np.concatenate([old, values])
        size = len(self._raw["q"])
        end = self._start + size - self.reach
        if end <= self.emitted:
            return None
        first, last = self.emitted - self._start, end - self._start  # buffer positions of the outputs
        raw = self._raw
        if self.window is None:
            q, qd, qdd = (raw[name][first:last] for name in ("q", "qd", "qdd"))
            X = np.column_stack([term.column(q, qd, qdd) for term in self.terms]) if self.terms else \
                np.empty((last - first, 0))
            tau = raw["tau"][first:last]
        else:
            half, h = self.half, self.step
            self._largest = max(self._largest, float(np.max(np.abs(raw["q"]))))
            floor = ROUNDING_FLOOR * self._largest
            span = slice(first - self.reach, last + self.reach)
            smoothed = np.correlate(raw["q"][span], self.weights, mode="valid")  # [first-half-2, last+half+2)
            velocity = (smoothed[2:] - smoothed[:-2]) / (2 * h)  # [first-half-1, last+half+1)
            acceleration = (velocity[2:] - velocity[:-2]) / (2 * h)  # [first-half, last+half)
            velocity = velocity[1:-1]
            velocity[np.abs(velocity) <= floor / h] = 0.0  # rounding has no sign (Coulomb's column), as offline
            # An acceleration at the level of rounding is none (offline: when the whole log's is): no column of
            # rounding noise for the fit to scale up into a 'determined' inertia.
            acceleration[np.abs(acceleration) <= floor / h / h] = 0.0
            wide = raw["q"][first - half: last + half]
            inner = slice(half, len(wide) - half)
            columns_out = []
            for term in self.terms:
                if term.from_derivatives:
                    column = np.asarray(term.column(wide[inner], velocity[inner], acceleration[inner]), dtype=float)
                else:
                    values = np.broadcast_to(np.asarray(term.column(wide, velocity, acceleration), dtype=float),
                                             wide.shape)
                    column = np.correlate(values, self.weights, mode="valid")
                columns_out.append(column)
            X = np.column_stack(columns_out) if columns_out else np.empty((last - first, 0))
            tau = np.correlate(raw["tau"][first - half: last + half], self.weights, mode="valid")
            q, qd, qdd = wide[inner], velocity[inner], acceleration[inner]
        out = {"X": X, "tau": tau, "q": q, "qd": qd, "qdd": qdd, "t": raw["t"][first:last],
               "index": np.arange(self.emitted, end)}
        self.emitted = end
        keep = self.emitted - self.reach - self._start  # the next outputs read from here on
        if keep > 0:
            self._raw = {name: values[keep:] for name, values in self._raw.items()}
            self._start += keep
        return out


def _held(buffers) -> int:
    """Numbers held in a dict of arrays (a stage's buffer)."""
    return sum(values.size for values in buffers.values())


class LowPassStream:
    """The parallel low-pass and decimation of full-rate columns as they arrive, at the kept rows only."""

    def __init__(self, chosen: ParallelFilter):
        """`chosen`: the low-pass and decimation (inactive: decimation alone)."""
        self.chosen = chosen
        self.decimation = chosen.decimation
        self.taps = None if chosen.design is None else chosen.design.taps
        self.half = 0 if self.taps is None else chosen.design.half
        self._columns: np.ndarray | None = None
        self._start = 0
        """Segment index of the buffer's first row."""
        self.next_row = None
        """The next kept row's index in decimated rows (row m is segment sample m x decimation)."""

    @property
    def size(self) -> int:
        """Numbers its buffer holds."""
        return 0 if self._columns is None else self._columns.size

    def add(self, columns: np.ndarray, first: int) -> tuple[np.ndarray, np.ndarray]:
        """Append (n, k) columns of segment samples first .. first + n - 1 (contiguous with the last call's); return
        (kept rows' indices m (r,), their low-passed columns (r, k))."""
        if self._columns is None:
            self._columns, self._start = columns, first
            # The first kept row whose window starts within what arrived.
            self.next_row = -(-(first + self.half) // self.decimation)
        else:
            self._columns = np.concatenate([self._columns, columns])
        end = self._start + len(self._columns)  # one past the last sample held
        last_row = (end - 1 - self.half) // self.decimation  # the last row whose window has arrived
        rows = np.arange(self.next_row, last_row + 1)
        if not len(rows):
            return rows, np.empty((0, columns.shape[1]))
        centres = rows * self.decimation - self._start
        if self.taps is None:
            out = self._columns[centres]
        else:
            windows = np.lib.stride_tricks.sliding_window_view(self._columns, len(self.taps), axis=0)
            out = np.einsum("rkl,l->rk", windows[centres - self.half], self.taps)
        self.next_row = int(rows[-1]) + 1
        drop = self.next_row * self.decimation - self.half - self._start
        if drop > 0:
            self._columns = self._columns[drop:]
            self._start += drop
        return rows, out


def triangle_update(triangle: np.ndarray | None, rows: np.ndarray) -> np.ndarray:
    """The (k, k) upper triangle R of [previous rows; `rows`] (R^T R = Z^T Z), from the previous triangle."""
    stacked = rows if triangle is None else np.vstack([triangle, rows])
    upper = np.linalg.qr(stacked, mode="r")
    width = stacked.shape[1]
    if upper.shape[0] < width:
        upper = np.vstack([upper, np.zeros((width - upper.shape[0], width))])
    return upper


@dataclass
class Batch:
    """A contiguous stretch of fitted rows: its triangle, row count and column sums (residual sums need them)."""

    triangle: np.ndarray
    count: int
    sums: np.ndarray
    start: float
    """Seconds watched at its first row."""
    grid: int = 0
    """Rows of the grid it spans (rows left out included)."""
    lagged: LaggedSums | None = None
    """Its Newey-West sums (pairs within it, and pairs reaching back into the batch before), or None."""


@dataclass
class LaggedSums:
    """Bartlett-weighted lagged sums of a stretch of grid rows at one lag L, from which the Newey-West covariance of
    the stretch's rows follows for any estimate (as NeweyWestSums, the weights applied as the pairs are added):
    lag 0, the pairs within the stretch at lags 1..L, and the pairs whose earlier row lies before it."""

    fourth0: np.ndarray
    fourth: np.ndarray
    fourth_back: np.ndarray
    second0: np.ndarray
    second: np.ndarray
    second_back: np.ndarray

    @classmethod
    def zeros(cls, columns: int) -> LaggedSums:
        """Empty sums for `columns` (p) regressor columns."""
        width = columns * (columns + 1)
        return cls(*(np.zeros((width, width)) for _ in range(3)),
                   *(np.zeros((columns + 1, columns + 1)) for _ in range(3)))

    def joined(self, later: LaggedSums) -> LaggedSums:
        """The sums of this stretch followed by `later` (its pairs reaching back now lie within)."""
        return LaggedSums(self.fourth0 + later.fourth0, self.fourth + later.fourth + later.fourth_back,
                          self.fourth_back, self.second0 + later.second0,
                          self.second + later.second + later.second_back, self.second_back)

    @property
    def size(self) -> int:
        """Numbers held."""
        return sum(values.size for values in vars(self).values())


class BatchStatistics:
    """The least-squares statistics of rows [X | y] arriving in blocks, in bounded memory."""

    def __init__(self, columns: int, batch_rows: int, lag: int | None = None):
        """`columns`: p; `batch_rows`: the shortest batch (rows of the grid); `lag`: each batch keeps the
        Newey-West sums of Bartlett lag `lag` (None: not kept), so any run of batches has its own errors."""
        self.columns = columns
        self.batch_rows = max(1, batch_rows)
        self.lag = lag
        self.triangle: np.ndarray | None = None
        self.count = 0
        self.closed: list[Batch] = []
        self.open: Batch | None = None
        width = columns * (columns + 1)
        self._tail_v = np.zeros((lag or 0, width))
        self._tail_z = np.zeros((lag or 0, columns + 1))

    def add(self, X: np.ndarray, y: np.ndarray, when: float, kept: np.ndarray | None = None) -> None:
        """Add rows (n, p) and (n,) of the grid, `when` seconds watched at the first; `kept` (n,) False where a row
        is left out (a gap in the grid: not fitted, no pair with it)."""
        if not len(y):
            return
        kept = np.ones(len(y), dtype=bool) if kept is None else np.asarray(kept, dtype=bool)
        Z = np.column_stack([X, y]) * kept[:, None]
        if kept.any():
            self.triangle = triangle_update(self.triangle, Z[kept])
        self.count += int(kept.sum())
        position = 0
        while position < len(Z):
            if self.open is None:
                self.open = Batch(np.zeros((0, Z.shape[1])), 0, np.zeros(Z.shape[1]), when,
                                  lagged=None if self.lag is None else LaggedSums.zeros(self.columns))
            room = self.batch_rows - self.open.grid
            piece, inside = Z[position: position + room], kept[position: position + room]
            if inside.any():
                self.open.triangle = triangle_update(self.open.triangle, piece[inside])
            self.open.count += int(inside.sum())
            self.open.sums = self.open.sums + piece.sum(axis=0)
            if self.lag is not None:
                self._add_lagged(piece)
            self.open.grid += len(piece)
            position += len(piece)
            if self.open.grid >= self.batch_rows:
                self.closed.append(self.open)
                self.open = None
                if len(self.closed) > MAX_BATCHES:
                    self._merge()

    def _merge(self) -> None:
        """Adjacent batches merged pairwise (an odd last one kept): half as many, twice as long."""
        merged = []
        for k in range(0, len(self.closed) - 1, 2):
            a, b = self.closed[k], self.closed[k + 1]
            merged.append(Batch(triangle_update(a.triangle, b.triangle), a.count + b.count, a.sums + b.sums,
                                a.start, a.grid + b.grid,
                                None if a.lagged is None else a.lagged.joined(b.lagged)))
        if len(self.closed) % 2:
            merged.append(self.closed[-1])
        self.closed = merged
        self.batch_rows *= 2

    def _add_lagged(self, Z: np.ndarray) -> None:
        """Add grid rows to the open batch's lagged sums: each pair (i, i + k), k <= lag, whose later row is new,
        as within the batch or reaching back before it."""
        lag, n, sums = self.lag, len(Z), self.open.lagged
        X = Z[:, :-1]
        V = (X[:, :, None] * Z[:, None, :]).reshape(n, -1)
        every_v, every_z = np.vstack([self._tail_v, V]), np.vstack([self._tail_z, Z])
        before = self.open.grid  # rows of the batch before these
        sums.fourth0 += V.T @ V
        sums.second0 += Z.T @ Z
        for k in range(1, lag + 1):
            weight = 1.0 - k / (lag + 1)
            back = max(0, min(n, k - before))  # new rows whose partner k back lies before the batch
            earlier_v, earlier_z = every_v[lag - k: lag - k + n], every_z[lag - k: lag - k + n]
            sums.fourth_back += weight * earlier_v[:back].T @ V[:back]
            sums.second_back += weight * earlier_z[:back].T @ Z[:back]
            sums.fourth += weight * earlier_v[back:].T @ V[back:]
            sums.second += weight * earlier_z[back:].T @ Z[back:]
        self._tail_v, self._tail_z = every_v[-lag:] if lag else every_v[:0], every_z[-lag:] if lag else every_z[:0]

    def gap(self) -> None:
        """A break in the grid (another stretch of samples): no pair spans it."""
        self._tail_v[:] = 0.0
        self._tail_z[:] = 0.0

    def lagged_covariance(self, solution: LeastSquaresSolution, subset: list[Batch], columns=None
                          ) -> tuple[np.ndarray, float] | None:
        """(The Newey-West covariance of the column estimate of `subset`'s rows alone, the effective count), as
        estimation.uncertainty's newey_west of those rows at the kept lag; None without a unique fit."""
        if solution.estimate is None or not subset or subset[0].lagged is None:
            return None
        total = subset[0].lagged
        for batch in subset[1:]:
            total = total.joined(batch.lagged)
        return lagged_covariance(total.fourth0, total.fourth, total.second0, total.second, self.columns, solution,
                                 columns)

    @property
    def batches(self) -> list[Batch]:
        """Every batch, the open one last."""
        return self.closed + ([self.open] if self.open is not None and self.open.count else [])

    def solution(self, subset: list[Batch] | None = None, columns=None) -> LeastSquaresSolution | None:
        """jointid's column-scaled, pivoted least squares of every row (or of `subset`'s) on `columns` (indices; all
        by default), None before any row."""
        chosen = list(range(self.columns)) if columns is None else list(columns)
        if subset is None:
            if self.triangle is None:
                return None
            triangle, count = self.triangle, self.count
        else:
            triangle = triangle_update(None, np.vstack([batch.triangle for batch in subset]))
            count = sum(batch.count for batch in subset)
        # ||y - X theta|| = ||T_y - T_X theta|| for every theta and any of X's columns (T^T T = Z^T Z): the same
        # problem in p + 1 rows.
        return replace(solve_least_squares(triangle[:, chosen], triangle[:, self.columns]), row_count=count)

    @property
    def size(self) -> int:
        """Numbers held (the state's size, for memory checks)."""
        return sum(batch.triangle.size + batch.sums.size + (0 if batch.lagged is None else batch.lagged.size)
                   for batch in self.batches) + (0 if self.triangle is None else self.triangle.size) + \
            self._tail_v.size + self._tail_z.size


class NeweyWestSums:
    """The sums from which the Newey-West covariance of a log fit (estimation.uncertainty.newey_west) follows for
    any estimate theta and any lag up to `lags`, kept as rows arrive on their evenly spaced grid.

    With z_i = [x_i, y_i] and V_i = x_i z_i^T, the score is u_i = x_i e_i = V_i a for a = [-theta, 1], so
    sum_i u_i u_{i+k}^T = sum_cd A_k[:, c, :, d] a_c a_d with A_k = sum_i V_i (x) V_{i+k}: a fourth-order sum per
    lag, linear in the rows; and the residuals' autocorrelation sum_i e_i e_{i+k} = a^T C_k a, C_k = sum z_i z_{i+k}^T.
    """

    def __init__(self, columns: int, lags: int):
        """`columns`: p; `lags`: the longest lag a refresh may ask for."""
        self.columns, self.lags = columns, lags
        width = columns * (columns + 1)
        self.fourth = np.zeros((lags + 1, width, width))
        self.second = np.zeros((lags + 1, columns + 1, columns + 1))
        self._tail_v = np.zeros((lags, width))
        self._tail_z = np.zeros((lags, columns + 1))

    def add(self, X: np.ndarray, y: np.ndarray) -> None:
        """Rows on the grid, next to the last ones; a row left out is given as zeros (a gap in the grid)."""
        n = len(y)
        if not n:
            return
        Z = np.column_stack([X, y])
        V = (X[:, :, None] * Z[:, None, :]).reshape(n, -1)
        every_v = np.vstack([self._tail_v, V])
        every_z = np.vstack([self._tail_z, Z])
        lags = self.lags
        for k in range(lags + 1):
            # Pairs (i, i + k) whose later row is new: each pair counted once over all blocks.
            self.fourth[k] += every_v[lags - k: lags - k + n].T @ V
            self.second[k] += every_z[lags - k: lags - k + n].T @ Z
        self._tail_v, self._tail_z = every_v[-lags:] if lags else every_v[:0], every_z[-lags:] if lags else every_z[:0]

    def gap(self) -> None:
        """A break in the grid (another stretch of samples): no pair spans it."""
        self._tail_v[:] = 0.0
        self._tail_z[:] = 0.0

    def covariance(self, solution: LeastSquaresSolution, lag: int, columns=None) -> tuple[np.ndarray, float] | None:
        """(The Newey-West covariance of the column estimate, the effective count), as estimation.uncertainty's
        newey_west of the same rows with Bartlett weights over `lag` (at most `lags`) steps; None without a unique
        fit."""
        if solution.estimate is None:
            return None
        lag = min(lag, self.lags)
        fourth0, second0 = self.fourth[0], self.second[0]
        weights = 1.0 - np.arange(1, lag + 1) / (lag + 1)
        fourth = np.tensordot(weights, self.fourth[1:lag + 1], axes=1)
        second = np.tensordot(weights, self.second[1:lag + 1], axes=1)
        return lagged_covariance(fourth0, fourth, second0, second, self.columns, solution, columns)

    @property
    def size(self) -> int:
        """Numbers held."""
        return self.fourth.size + self.second.size + self._tail_v.size + self._tail_z.size


def lagged_covariance(fourth0: np.ndarray, fourth: np.ndarray, second0: np.ndarray, second: np.ndarray, total: int,
                      solution: LeastSquaresSolution, columns=None) -> tuple[np.ndarray, float]:
    """(Newey-West covariance of the column estimate, effective count) from lag-0 and Bartlett-weighted lagged sums
    (NeweyWestSums' fourth- and second-order sums) of rows with `total` regressor columns."""
    theta = solution.estimate
    chosen = list(range(total)) if columns is None else list(columns)
    with_y = [*chosen, total]
    p, count = len(chosen), solution.row_count
    a = np.append(-theta, 1.0)

    def moment(sums: np.ndarray) -> np.ndarray:
        """sum_i u_i u_(i+k)^T of the sums at the estimate."""
        picked = sums.reshape(total, total + 1, total, total + 1)[np.ix_(chosen, with_y, chosen, with_y)]
        return np.einsum("acbd,c,d->ab", picked, a, a)

    lagged = moment(fourth)
    meat = moment(fourth0) + lagged + lagged.T
    meat = (meat + meat.T) / 2
    c0 = float(a @ second0[np.ix_(with_y, with_y)] @ a)
    shared = 2 * float(a @ second[np.ix_(with_y, with_y)] @ a)
    factor = covariance_factor(solution)
    autocorrelation = max((c0 + shared) / c0, 1.0) if c0 > 0 else 1.0
    return factor @ meat @ factor * count / max(count - p, 1), count / autocorrelation


class SplineResampler:
    """Jittered samples onto a uniform grid as they arrive, as jointid.logs.timing.resample does a whole log: a
    not-a-knot cubic spline, here through the samples around each grid time (MARGIN either side), whose value
    there differs from the whole log's spline by far less than the spline's own error (a spline's dependence on
    a far sample decays about 3.7 times per sample)."""

    MARGIN = 12
    """Samples either side of a grid time the spline is fitted through."""

    def __init__(self, step: float):
        """`step`: the grid's step (s), the median step of the warm-up."""
        self.step = step
        self._raw: dict[str, np.ndarray] = {}
        self._origin: float | None = None
        self._next = 0
        """The next grid time's index: origin + index x step."""

    @property
    def size(self) -> int:
        """Numbers its buffer holds."""
        return _held(self._raw)

    def add(self, columns: dict[str, np.ndarray]) -> dict[str, np.ndarray] | None:
        """Append samples (t and other columns); return the grid times now surrounded by MARGIN samples and every
        column there, or None."""
        from scipy.interpolate import CubicSpline  # lazily, as the offline resampling: only jittered sources

        for name, values in columns.items():
            old = self._raw.get(name)
            self._raw[name] = values if old is None else np.concatenate([old, values])
        t = self._raw["t"]
        increasing = np.concatenate([[True], np.diff(t) > 0])
        if not increasing.all():  # a repeated stamp cannot be placed: dropped, as a log's exact repeats
            self._raw = {name: values[increasing] for name, values in self._raw.items()}
            t = self._raw["t"]
        if self._origin is None:
            self._origin = float(t[0])
        margin = self.MARGIN
        if len(t) < 2 * margin + 2:
            return None
        low, high = t[margin], t[len(t) - 1 - margin]
        first = max(self._next, int(np.ceil((low - self._origin) / self.step - 1e-9)))
        last = int(np.floor((high - self._origin) / self.step + 1e-9))
        if last < first:
            return None
        grid = self._origin + self.step * np.arange(first, last + 1)
        names = [name for name in self._raw if name != "t"]
        spline = CubicSpline(t, np.column_stack([self._raw[name] for name in names]), axis=0)
        values = spline(grid)
        self._next = last + 1
        # Keep the samples the next grid time's spline reads.
        upcoming = self._origin + self._next * self.step
        keep = max(0, int(np.searchsorted(t, upcoming)) - 1 - margin)
        self._raw = {name: values_[keep:] for name, values_ in self._raw.items()}
        out = {"t": grid}
        out.update({name: np.ascontiguousarray(values[:, j]) for j, name in enumerate(names)})
        return out
