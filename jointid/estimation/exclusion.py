"""Which samples of a filtered log a fit leaves out: outside torques found by a robust fit, and standstill.

A real joint's log holds stretches the model cannot describe: a hand pushing
the link, a collision, a cable snag (an outside torque the log does not
record), and standstill, where friction is static and takes any value up to
breakaway rather than Fc sign(qd). Least squares lets such samples pull every
parameter; here they are found and left out.

Outside torques are outliers in time. A high-breakdown start (FAST-LTS,
Rousseeuw and Van Driessen 2006: random elemental starts and concentration
steps, half of the samples trimmed) finds the fit of the majority, a Tukey
bisquare M-step with that scale fixed (the MM estimator, Yohai 1987) brings
back the informative large-torque samples LTS trimmed, and residuals are then
judged on that robust scale (MAD). A stretch is flagged when some residual in
it stands above the level a clean log would reach with probability 1 % (for
its effective number of independent residuals: filtered residuals are
correlated), and it extends as far as its residuals stay above 2 scales.
Flagged stretches closer than twice the filter's support are merged, and each
one inside the log is widened by a quarter of the support (about 0.22 /
cutoff: the core of the filter's main lobe, where a push's edge still weighs
70 % or more of its centre though its residual fell below 2 scales).

Standstill: where the filtered speed stays below a tenth of its RMS (and three
velocity resolutions), the joint sticks; rests longer than the filter's
support are widened by it, since the filtered friction column is smeared that
far. Only models with a Coulomb term leave standstill out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..norms import rms
from .solver import PRODUCT_PIECE
from .uncertainty import newey_west_sum

COVERAGE = 0.5
"""LTS keeps this share of the samples: it tolerates up to half of them being outliers."""
STARTS = 200
"""Random elemental starts of FAST-LTS."""
SUBSAMPLE = 1000
"""FAST-LTS runs its starts on at most this many samples, then refines the best two on all of them. 1000 rather than
1500 moves the robust estimate by up to a few percent through its scale but no flag on the bench logs, the real runs
or the synthetic pushes (the fit itself is the least squares of what is kept), and brought ten pooled runs from
1.21 to 1.17 times their concatenation (bench_robust, 2026-11-25 23:37)."""
BISQUARE = 4.685
"""Tukey's bisquare constant (95 % efficiency for Gaussian residuals)."""
FALSE_ALARM = 0.01
"""The chance that a clean log has some stretch flagged."""
EXTENT = 2.0
"""A flagged stretch extends while residuals stay above this many robust scales."""
WIDENING = 0.25
"""Filter supports each stretch inside the log is widened by: a quarter met both of issue 23's goals (at most 10 %
left out beyond three synthetic pushes, the energy-shaping run predicted at most half as badly as published),
where half left out 11-14 % (benchmarks/push_widening_study.py)."""
STANDSTILL_SHARE = 0.1
"""Speeds below this share of the RMS filtered speed count as standstill."""
BREAKAWAY_RATIO = 1.5
"""At rest, friction may reach this many times Fc (breakaway): only residuals beyond it count as a push."""
EXACT = 1e-12
"""Residuals below this share of the torque's RMS are rounding: the model fits exactly."""
SEED = 0
"""The random starts' seed, so a log always gives the same exclusions."""


@dataclass(frozen=True, eq=False)
class Exclusions:
    """The samples (of the decimated grid) a fit leaves out, and why."""

    pushes: np.ndarray
    """(n,) True where an outside torque acts (found by the robust step or given by hand)."""
    standstill: np.ndarray
    """(n,) True where the joint sticks (only with a Coulomb term)."""
    speed_threshold: float | None
    """rad/s below which a sample is standstill, or None when standstill is kept."""
    level: float | None
    """Robust scales a residual must exceed to start a flagged stretch, or None without the robust step."""
    since: np.ndarray
    """(n,) Each sample's time from the log's start (s)."""
    estimate: np.ndarray | None = None
    """The robust step's estimate of the filtered columns' coefficients, or None without it."""
    times: np.ndarray | None = None
    """(n,) The samples' times as the log gives them (s), for charts of every sample, kept or not."""
    regressor: np.ndarray | None = None
    """(n, p) The filtered regressor of every sample, kept or not: the rows these decisions were made on."""
    torque: np.ndarray | None = None
    """(n,) The filtered torque of every sample, kept or not."""

    @property
    def excluded(self) -> tuple[tuple[float, float], ...]:
        """[start, end] seconds from the log's start of each stretch left out for an outside torque."""
        return intervals(self.pushes, self.since)

    @property
    def within(self) -> tuple[tuple[float, float], ...]:
        """The excluded stretches that touch neither end of the log: outside torques (pushes, by hand)."""
        first, last = float(self.since[0]), float(self.since[-1])
        return tuple(stretch for stretch in self.excluded if stretch[0] > first and stretch[1] < last)

    @property
    def at_ends(self) -> tuple[tuple[float, float], ...]:
        """The excluded stretches at the log's ends, where the smoothing and the low-pass reach past the log."""
        return tuple(stretch for stretch in self.excluded if stretch not in self.within)

    @property
    def excluded_share(self) -> float:
        """The share of the samples left out for outside torques."""
        return float(self.pushes.mean()) if len(self.pushes) else 0.0

    @property
    def standstill_share(self) -> float:
        """The share of the samples left out as standstill."""
        return float(self.standstill.mean()) if len(self.standstill) else 0.0

    @property
    def kept(self) -> np.ndarray:
        """(n,) True for the samples the fit uses."""
        return ~(self.pushes | self.standstill)


def mad_scale(residuals: np.ndarray) -> float:
    """1.4826 x the median absolute deviation: the standard deviation of Gaussian residuals, robustly."""
    return 1.4826 * float(np.median(np.abs(residuals - np.median(residuals))))


def fast_lts(X: np.ndarray, y: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """The least-trimmed-squares estimate: minimises the sum of the COVERAGE share of smallest squared residuals.

    The starts' concentration steps run together (one product, one partition and one stack of small solves for
    all of them per step).
    """
    n, p = X.shape
    sub = np.arange(n) if n <= SUBSAMPLE else np.sort(rng.choice(n, SUBSAMPLE, replace=False))
    draws = np.array([rng.choice(sub, p, replace=False) for _ in range(STARTS)])
    solutions, ranks = _elemental_fits(X[draws], y[draws])
    full = ranks == p
    if not full.any():  # no p rows of full rank among the draws: the data cannot single out a majority fit
        return np.linalg.lstsq(X, y, rcond=None)[0]
    values, thetas = _concentrated(X[sub], y[sub], solutions[full], 2)
    order = np.argsort(values, kind="stable")[:10]
    keep = max(p + 1, int(COVERAGE * len(sub)))
    if values[order[0]] <= keep * (EXACT * rms(y)) ** 2:
        # Half the samples fitted to rounding (a model that fits exactly): the trimmed sum's least value is
        # reached, and further steps only move rounding about (on a noise-free log they took half the time).
        return thetas[order[0]]
    values, thetas = _concentrated(X[sub], y[sub], thetas[order], 30)
    order = np.argsort(values, kind="stable")
    if len(sub) < n:
        values, thetas = _concentrated(X, y, thetas[order[:2]], 30)
        order = np.argsort(values, kind="stable")
    return thetas[order[0]]


def _elemental_fits(A: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(K, p) least-squares solutions and (K,) ranks of K square systems A (K, p, p) x = b (K, p), as
    np.linalg.lstsq gives them one by one (rank: singular values above p eps times the largest)."""
    u, singular, vt = np.linalg.svd(A)
    ranks = (singular > A.shape[-1] * np.finfo(float).eps * singular[:, :1]).sum(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        inverse = np.where(np.arange(A.shape[-1]) < ranks[:, None], 1.0 / singular, 0.0)
    solutions = np.einsum("kji,kj,kjl,kl->ki", vt, inverse, u.transpose(0, 2, 1), b)
    return solutions, ranks


def _concentrated(X: np.ndarray, y: np.ndarray, thetas: np.ndarray, steps: int) -> tuple[np.ndarray, np.ndarray]:
    """((K,) trimmed sums of squares, (K, p) estimates) after up to `steps` concentration steps from each of the
    K `thetas`: refit to the COVERAGE share of smallest squared residuals until the trimmed sum stops falling."""
    n, p = X.shape
    keep = max(p + 1, int(COVERAGE * n))
    thetas = np.array(thetas, dtype=float)
    objectives = np.full(len(thetas), math.inf)
    thresholds = np.full(len(thetas), math.nan)
    active = np.arange(len(thetas))
    # Small sets' Gram matrices as one product of the chosen-row masks with every row's outer product.
    augmented = np.column_stack([X, y])
    outer = (augmented[:, :, None] * augmented[:, None, :]).reshape(n, -1) \
        if (p + 1) ** 2 * keep < PRODUCT_PIECE else None
    # Two (K, n) buffers for every step's squares and their partition: fresh arrays of that size each step
    # (page faults on this VM) cost as much as the partition itself.
    buffers = np.empty((2, len(thetas), n))
    direct = False
    for _ in range(steps):
        if not len(active):
            break
        squares = _squared_residuals(X, y, thetas[active], buffers[0, :len(active)])
        values, chosen, found, failed = _smallest(squares, keep, thresholds[active], buffers[1, :len(active)],
                                                  direct)
        # Squares with many ties (a model that fits exactly: multiples of eps^2) leave most thresholds unsure:
        # the following steps go to np.argpartition at once rather than looking first.
        direct = direct or failed > len(active) // 2
        going = values < objectives[active] * (1 - 1e-9)
        active, chosen = active[going], chosen[going]
        objectives[active], thresholds[active] = values[going], found[going]
        if len(active):
            thetas[active] = _refits(X, y, chosen, thetas[active], outer, buffers[1, :len(active)])
    return _smallest(_squared_residuals(X, y, thetas, buffers[0]), keep, thresholds, buffers[1], direct)[0], thetas


BAND = 0.05
"""A row's keep-th smallest square is first looked for within this share of the previous step's."""


def _smallest(squares: np.ndarray, keep: int, guesses: np.ndarray, work: np.ndarray, direct: bool = False
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """((K,) sums of each row's `keep` smallest squares, (K, n) True at them, (K,) the keep-th smallest or a
    threshold between it and the next, how many rows' thresholds failed to pick exactly `keep`); `work` is a
    (K, n) buffer to partition in; `direct`: every row by np.argpartition.

    A comparison with each row's keep-th smallest rather than np.argpartition, which moves indices beside the
    values. Many rows (the starts' first steps) find it by a partition of float32 roundings (see `_located`);
    a few look for it first among the values near `guesses` (the previous step's, NaN for none), since a
    concentration step moves it little: a partition of all of them each step took a third of the steps' time
    on a 1e6-row log. A row whose comparison does not pick exactly `keep` (ties at the boundary, NaN) takes
    np.argpartition's choice.
    """
    K, n = squares.shape
    if direct:
        kth = np.full(K, math.nan)
    elif K > 10:
        kth = _located(squares, keep, work)
    else:
        kth = np.full(K, math.nan)
        for k, guess in enumerate(guesses):
            if not guess > 0:
                continue
            row = squares[k]
            below = int(np.count_nonzero(row < guess * (1 - BAND)))
            near = row[(row >= guess * (1 - BAND)) & (row <= guess * (1 + BAND))]
            if below < keep <= below + len(near):
                kth[k] = np.partition(near, keep - 1 - below)[keep - 1 - below]
    # Rows whose threshold does not pick exactly `keep` (none found, ties at the boundary, NaN, or squares too
    # small for float32, as where the model fits exactly) take np.argpartition's choice, all in one call.
    if direct:
        chosen, unsure, failed = None, np.arange(K), K
    else:
        with np.errstate(invalid="ignore"):  # a NaN threshold picks nothing, and the row goes below
            chosen = squares <= kth[:, None]
        unsure = np.flatnonzero(np.count_nonzero(chosen, axis=1) != keep)
        failed = int(np.count_nonzero(~np.isnan(kth[unsure])))
    if len(unsure):
        rows = squares if len(unsure) == K else squares[unsure]
        picks = np.argpartition(rows, keep - 1, axis=1)[:, :keep]
        picked = np.zeros(rows.shape, dtype=bool)
        np.put_along_axis(picked, picks, True, axis=1)
        if len(unsure) == K:
            chosen = picked
        else:
            chosen[unsure] = picked
        kth[unsure] = np.take_along_axis(rows, picks, axis=1).max(axis=1)
    with np.errstate(all="ignore"):  # an infinite square left out would make NaN: summed again below
        values = np.einsum("ij,ij->i", squares, chosen)  # sum(where=) took four times as long
    for k in np.flatnonzero(~np.isfinite(values)):
        values[k] = squares[k, chosen[k]].sum()
    return values, chosen, kth, failed


def _located(squares: np.ndarray, keep: int, work: np.ndarray) -> np.ndarray:
    """(K,) for each row a threshold at or above its keep-th smallest square and below the next one unless
    another square rounds to the same float32 (which `_smallest`'s count then finds), or NaN where this way
    cannot say.

    Rounding to float32 keeps the order, so the keep-th smallest rounding is the rounding of the keep-th
    smallest square, and the midpoint between it and the next float32 bounds every square that rounds to it.
    The partition moves half the bytes: on the 200 starts' (200, 1500) squares it took 1.6 ms against 2.9 ms.
    """
    K, n = squares.shape
    coarse = work.reshape(-1).view(np.float32)[:K * n].reshape(K, n)
    with np.errstate(all="ignore"):  # squares beyond float32's range round to infinity: such rows are left out
        np.copyto(coarse, squares, casting="same_kind")
        coarse.partition(keep - 1, axis=1)
        rounded = coarse[:, keep - 1]
        bound = (rounded.astype(float) + np.nextafter(rounded, np.float32(np.inf)).astype(float)) / 2
        bound[~(np.isfinite(rounded) & (rounded > 0))] = math.nan  # beyond float32's range (or NaN): in float64
    return bound


def _refits(X: np.ndarray, y: np.ndarray, chosen: np.ndarray, thetas: np.ndarray, outer: np.ndarray | None,
            work: np.ndarray) -> np.ndarray:
    """(K, p) least-squares estimates on each of the K row sets `chosen` (K, n masks), the previous estimates
    `thetas` (K, p) their starting points; `work` a (K, n) buffer.

    Small sets together, by their Gram matrices: the masks times `outer` (n, (p + 1)^2, each row's outer
    product with the torque beside it), in products under OpenBLAS's threading size; one np.linalg.lstsq per
    set took most of the 200 starts' time. The columns are scaled to about 1 (see `outside_torques`), so
    squaring their condition costs nothing the concentration steps could notice; a set whose Gram matrix is
    singular goes through np.linalg.lstsq. Large sets (`outer` None) one by one, as a correction to their
    previous estimate (see `_corrected`).
    """
    K, n = chosen.shape
    p = X.shape[1]
    if outer is None or K == 1:
        return np.array([_corrected(X[rows], y[rows], theta) for rows, theta in zip(chosen, thetas)])
    masks = work
    np.copyto(masks, chosen)
    gram = np.zeros((K, outer.shape[1]))
    piece = max(1, PRODUCT_PIECE // (K * outer.shape[1]))
    for first in range(0, n, piece):
        gram += masks[:, first:first + piece] @ outer[first:first + piece]
    gram = gram.reshape(K, p + 1, p + 1)
    out = np.empty((K, p))
    singular = np.zeros(K, dtype=bool)
    try:
        out[:] = np.linalg.solve(gram[:, :p, :p], gram[:, :p, p:])[..., 0]
    except np.linalg.LinAlgError:
        singular[:] = True
    singular |= ~np.isfinite(out).all(axis=1)
    for k in np.flatnonzero(singular):
        out[k] = np.linalg.lstsq(X[chosen[k]], y[chosen[k]], rcond=None)[0]
    return out


GRAM_CONDITION = 1e10
"""Above this condition of the Gram matrix a weighted least-squares step goes through np.linalg.lstsq."""


def _corrected(X: np.ndarray, y: np.ndarray, theta: np.ndarray, weights: np.ndarray | None = None) -> np.ndarray:
    """The (weighted) least-squares estimate of y on X, as the correction to `theta` that the normal equations
    give for its residuals.

    np.linalg.lstsq (an SVD) took 1-5 ms per call on tens of thousands of rows and most of the robust step's
    time; the normal equations square the columns' condition, but they only solve for the correction, whose
    own error (condition^2 eps times the correction) the next step corrects again: the iterations converge to
    what lstsq gives. An ill-conditioned Gram matrix (GRAM_CONDITION) still goes through np.linalg.lstsq.
    """
    p = X.shape[1]
    gram = np.zeros((p, p))
    score = np.zeros(p)
    # In pieces below 2^18 multiply-adds, which OpenBLAS runs on one thread (see PRODUCT_PIECE).
    piece = max(1, PRODUCT_PIECE // (p * (p + 1)))
    for first in range(0, len(y), piece):
        rows = X[first:first + piece]
        block = (rows if weights is None else rows * weights[first:first + piece, None]).T
        gram += block @ rows
        score += block @ (y[first:first + piece] - rows @ theta)
    with np.errstate(all="ignore"):  # np.linalg.cond's checks took as long as the SVD itself
        singular = np.linalg.svd(gram, compute_uv=False) if np.all(np.isfinite(gram)) else np.zeros(1)
        condition = singular[0] / singular[-1] if singular[-1] > 0 else math.inf
    if not condition <= GRAM_CONDITION:
        root = np.ones(len(y)) if weights is None else np.sqrt(weights)
        return np.linalg.lstsq(X * root[:, None], y * root, rcond=None)[0]
    return theta + np.linalg.solve(gram, score)


def _squared_residuals(X: np.ndarray, y: np.ndarray, thetas: np.ndarray, out: np.ndarray) -> np.ndarray:
    """(K, n) squared residuals of each of the K estimates, a row each (contiguous for the partition), in `out`."""
    # Products below 2^18 multiply-adds, which OpenBLAS runs on one thread: waking its threads for each one
    # made the 200 starts' steps three times slower on this busy 2-core machine.
    piece = max(1, PRODUCT_PIECE // max(1, X.size))
    for first in range(0, len(thetas), piece):
        np.matmul(thetas[first:first + piece], X.T, out=out[first:first + piece])
    np.subtract(y, out, out=out)
    return np.square(out, out=out)


def bisquare(X: np.ndarray, y: np.ndarray, theta: np.ndarray, scale: float) -> np.ndarray:
    """Tukey-bisquare M-estimate from `theta` with the scale fixed (iteratively reweighted least squares)."""
    if not scale > 0:  # most residuals exactly zero (a SysId test's constant voltage, fitted exactly): no outlier
        return theta
    for _ in range(50):
        u = (y - X @ theta) / (BISQUARE * scale)
        new = _corrected(X, y, theta, np.where(np.abs(u) < 1, (1 - u * u) ** 2, 0.0))
        with np.errstate(all="ignore"):  # np.allclose's test, without its overhead (a tenth of an iteration)
            close = np.all(np.abs(new - theta) <= 1e-12 + 1e-8 * np.abs(theta))
        if close:
            return new
        theta = new
    return theta


def runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) indices of each run of True in `mask`."""
    return list(zip(*_run_ends(mask)))


def widened(mask: np.ndarray, count: int) -> np.ndarray:
    """`mask` with every run of True grown by `count` samples on each side."""
    if count <= 0 or not mask.any():
        return mask.copy()
    return np.convolve(mask.astype(float), np.ones(2 * count + 1), mode="same") > 0.5


DIRECT_LAGS = 100
"""Up to this many lags the effective count sums them one by one; beyond, by FFT (newey_west_sum)."""


def effective_count(residuals: np.ndarray, kept: np.ndarray, lag: int) -> float:
    """How many independent residuals the kept ones are worth (Bartlett-weighted autocorrelation, gaps zeroed)."""
    positions = np.flatnonzero(kept)
    if not len(positions):
        return 0.0
    if lag > DIRECT_LAGS:
        _, autocorrelation = newey_west_sum(np.ones((len(positions), 1)), residuals[positions], positions, lag)
        return len(positions) / autocorrelation
    grid = np.zeros(positions[-1] - positions[0] + 1)
    grid[positions - positions[0]] = residuals[positions]
    c0 = float(np.einsum("i,i->", grid, grid))
    if not c0 > 0:
        return float(len(positions))
    # A dot product per lag (einsum: BLAS's would wake OpenBLAS's threads): newey_west_sum's FFTs of the whole
    # grid cost ten times more for the few dozen lags a decimated log has.
    total = c0 + 2 * sum((1 - k / (lag + 1)) * float(np.einsum("i,i->", grid[:-k], grid[k:]))
                         for k in range(1, min(lag, len(grid) - 1) + 1))
    return len(positions) / max(total / c0, 1.0)


def standstill(speed: np.ndarray, resolution: float, support: int) -> tuple[np.ndarray, np.ndarray, float]:
    """(standstill samples, the rests among them, the speed threshold) of a filtered speed (rad/s).

    `resolution` is the speed one encoder count makes over the filter; rests longer than the filter's support
    (samples) are widened by it.
    """
    threshold = max(STANDSTILL_SHARE * rms(speed), 3.0 * resolution)
    slow = np.abs(speed) < threshold
    rest = np.zeros_like(slow)
    for first, last in runs(slow):
        if last - first + 1 >= max(2, support):
            rest[first:last + 1] = True
    rest = widened(rest, support)
    return slow | rest, rest, threshold


def outside_torques(X: np.ndarray, y: np.ndarray, usable: np.ndarray, rest: np.ndarray, coulomb: int | None,
                    support: int, lag: int, start: np.ndarray | None = None
                    ) -> tuple[np.ndarray, float, np.ndarray | None]:
    """(True where an outside torque acts, the level in robust scales that starts a flagged stretch, the robust
    estimate of X's coefficients).

    `usable`: the samples the robust fit may use (standstill left out); `rest`: samples at rest, where
    friction up to BREAKAWAY_RATIO x Fc is static, not a push; `coulomb`: the Coulomb column's index or None;
    `start`: a robust estimate of the same joint already found (another filter of the same log), from which
    the bisquare step starts instead of a new high-breakdown search.
    """
    rng = np.random.default_rng(SEED)
    # In units where every column and the torque are about 1: the flags do not depend on units, and data of
    # extreme magnitude neither overflow nor underflow on the way.
    with np.errstate(all="ignore"):
        column_scale = np.max(np.abs(X), axis=0)
        column_scale[~(column_scale > 0) | ~np.isfinite(column_scale)] = 1.0
        torque_scale = float(np.max(np.abs(y))) or 1.0
        X, y = X / column_scale, y / torque_scale
    Xu, yu = X[usable], y[usable]
    with np.errstate(all="ignore"):  # a start from data of extreme magnitude: checked just below
        theta = None if start is None else start * column_scale / torque_scale
    if theta is None or not np.all(np.isfinite(theta)):
        theta = fast_lts(Xu, yu, rng)
    theta = bisquare(Xu, yu, theta, mad_scale(yu - Xu @ theta))
    with np.errstate(all="ignore"):  # in the log's units it may leave double range; the flags do not need it
        estimate = theta * torque_scale / column_scale
    residuals = y - X @ theta
    scale = mad_scale(residuals[usable])
    if not scale > EXACT * rms(y):  # an exact fit (noise-free data): nothing stands out
        return np.zeros(len(y), dtype=bool), math.inf, estimate
    z = np.abs(residuals) / scale
    if coulomb is not None:
        static = np.abs(residuals + theta[coulomb] * X[:, coulomb]) - BREAKAWAY_RATIO * abs(theta[coulomb])
        z = np.where(rest, np.maximum(static, 0.0) / scale, z)
    clean = usable & (z < 2.5)
    from statistics import NormalDist  # only log fits get here

    level = NormalDist().inv_cdf(1 - FALSE_ALARM / (2 * max(effective_count(residuals, clean, lag), 1.0)))
    # Each stretch's peak by one reduceat and the stretches marked by differences: a Python loop over the
    # thousands of stretches above EXTENT took a few ms a call.
    firsts, lasts = _run_ends(z > EXTENT)
    peaks = np.maximum.reduceat(np.append(z, 0.0), np.stack([firsts, lasts + 1], axis=1).ravel())[::2]
    high = peaks > level
    flagged = _marked(len(y), firsts[high], lasts[high])
    firsts, lasts = _run_ends(flagged)
    close = firsts[1:] - lasts[:-1] - 1 < 2 * support
    flagged |= _marked(len(y), lasts[:-1][close], firsts[1:][close] - 1)
    return widened_inside(flagged, int(round(WIDENING * support))), level, estimate


def widened_inside(mask: np.ndarray, count: int) -> np.ndarray:
    """`mask` with every run of True that touches neither end grown by `count` samples on each side (a run at an
    end is the log's edge, not a push: its extent is the smoothing's, already judged by its residuals)."""
    firsts, lasts = _run_ends(mask)
    inside = (firsts > 0) & (lasts < len(mask) - 1)
    if count <= 0 or not inside.any():
        return mask.copy()
    grown = _marked(len(mask), np.maximum(firsts[inside] - count, 0), np.minimum(lasts[inside] + count, len(mask) - 1))
    return mask | grown


def _run_ends(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(first indices, last indices) of the runs of True in `mask`, as arrays (see `runs`)."""
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1


def _marked(n: int, firsts: np.ndarray, lasts: np.ndarray) -> np.ndarray:
    """(n,) True from each of `firsts` to the matching one of `lasts` (inclusive; the spans apart)."""
    steps = np.zeros(n + 1, dtype=np.int64)
    np.add.at(steps, firsts, 1)
    np.add.at(steps, lasts + 1, -1)
    return np.cumsum(steps[:n]) > 0


def intervals(mask: np.ndarray, t: np.ndarray) -> tuple[tuple[float, float], ...]:
    """[start, end] seconds of each run of True in `mask` on the times `t`."""
    return tuple((float(t[first]), float(t[last])) for first, last in runs(mask))


@dataclass(frozen=True)
class ExclusionRequest:
    """What a log's fit leaves out: outside torques found by the robust step, and intervals given by hand."""

    robust: bool = True
    """Find and leave out stretches where an outside torque acts (`--no-robust` turns it off)."""
    by_hand: tuple[tuple[float, float], ...] = ()
    """[start, end] seconds from the log's start to leave out as well (`--exclude START:END`)."""


CHANGE_RATIO = 10.0
"""An effort that moves by this many times its median step between samples (and beyond CHANGE_SHARE of its range)
is a commanded change (a voltage step), not the slow drift of a ramp."""
CHANGE_SHARE = 0.05
"""The least change, as a share of the effort's largest magnitude, that counts as commanded."""


def commanded_changes(effort: np.ndarray, reach: int) -> np.ndarray:
    """(n,) True from each commanded change of the effort (a step, or a log that starts mid-step: its first effort
    far from rest) to `reach` samples after it: where the response to it, a transient, plays out."""
    n = len(effort)
    if n < 3:
        return np.zeros(n, dtype=bool)
    steps = np.abs(np.diff(effort))
    largest = float(np.max(np.abs(effort))) or 1.0
    jumps = (steps > CHANGE_RATIO * float(np.median(steps))) & (steps > CHANGE_SHARE * largest)
    changed = np.concatenate(([abs(float(effort[0])) > 0.5 * largest], jumps))
    firsts = np.flatnonzero(changed)
    if not len(firsts):
        return np.zeros(n, dtype=bool)
    return _marked(n, firsts, np.minimum(firsts + reach, n - 1))


def explained_transients(X: np.ndarray, y: np.ndarray, flagged: np.ndarray, usable: np.ndarray,
                         transient: np.ndarray, level: float) -> np.ndarray:
    """`flagged` less each stretch that meets a commanded change's transient and that the model explains: a least
    squares fit with the stretch kept leaves its residuals' RMS within `level` robust scales (a voltage step's
    response is where the acceleration gain's information is, not an outside torque; the RMS, since the first
    samples of a log that starts mid-step carry the smoothing's end effects)."""
    firsts, lasts = _run_ends(flagged)
    meets = [(first, last) for first, last in zip(firsts, lasts) if transient[first:last + 1].any()]
    if not meets or not math.isfinite(level):
        return flagged
    out = flagged.copy()
    for first, last in meets:
        stretch = np.zeros(len(y), dtype=bool)
        stretch[first:last + 1] = True
        rows = usable & (~flagged | stretch)
        if rows.sum() <= X.shape[1]:
            continue
        theta = np.linalg.lstsq(X[rows], y[rows], rcond=None)[0]
        residuals = y - X @ theta
        scale = mad_scale(residuals[rows & ~stretch]) if (rows & ~stretch).sum() > X.shape[1] else 0.0
        if rms(residuals[stretch]) <= level * scale + EXACT * rms(y):
            out[first:last + 1] = False
    return out
