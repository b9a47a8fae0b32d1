"""Time stamps as loggers record them: order checked, gaps refused, jitter resampled onto a uniform grid.

Real loggers jitter (a 300 Hz controller's steps spread by 12 % here) and the
Savitzky-Golay differentiator needs one sample interval. When derivatives must
be estimated, a log whose steps depart from their median by more than
UNIFORM_TOLERANCE is resampled onto a uniform grid at the median step by a
cubic spline through every column (not-a-knot ends): for smooth joint motion
its error is of order step^4 q'''', far below encoder quantisation, where
linear interpolation's step^2 q''/8 would reach it at 50 Hz. Steps within the
tolerance are used as they are (the differentiator then takes the median
step), as before. What resampling cannot repair is refused with the time named:

- time running backwards (a step below zero);
- a time stamp that repeats with different values, which cannot be ordered
  (a row repeated exactly, time and values, is dropped and counted in a note);
- a gap longer than GAP_FACTOR median steps, when derivatives are estimated:
  interpolating across it would invent motion. Fit the pieces as separate logs.

Logs that carry qd and qdd need no differentiation: their times are only
checked for order (and exact repeats), jitter and gaps are kept as recorded.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

UNIFORM_TOLERANCE = 0.01
"""Largest relative departure of a time step from the median step that is used without resampling."""

GAP_FACTOR = 5.0
"""A step longer than this many median steps is a gap, not jitter (a logger that missed four ticks)."""

INTERPOLATION = "cubic spline"
"""How jittered columns are resampled, as notes and JSON name it."""


@dataclass(frozen=True, eq=False)
class TimeCheck:
    """What the time column showed: its median step, jitter, repeats dropped, and any resampling."""

    step: float | None
    """Median time step (s), or None without a time column (or with one row)."""
    median_jitter: float
    """Median of |step - median step| / median step."""
    max_jitter: float
    """Largest |step - median step| / median step."""
    duplicates: int
    """Rows dropped because they repeated the previous row exactly (time and values)."""
    resampled: bool
    """True when the columns were interpolated onto a uniform grid at the median step."""
    rows_before: int
    """Rows before dropping repeats and resampling."""
    rows_after: int
    """Rows after."""

    @property
    def uniform(self) -> bool:
        """True when the samples (after any resampling) are evenly spaced within UNIFORM_TOLERANCE."""
        return self.step is not None and (self.resampled or self.max_jitter <= UNIFORM_TOLERANCE)

    def to_dict(self) -> dict:
        """Plain JSON-ready values."""
        return {
            "median_step": self.step,
            "median_jitter": self.median_jitter,
            "max_jitter": self.max_jitter,
            "duplicate_rows_dropped": self.duplicates,
            "resampled": self.resampled,
            "interpolation": INTERPOLATION if self.resampled else None,
            "rows_before": self.rows_before,
            "rows_after": self.rows_after,
        }

    @property
    def descriptions(self) -> tuple[str, ...]:
        """Sentences for a person: repeats dropped, and how jittered time was resampled (none if neither)."""
        out = []
        if self.duplicates:
            rows = "row" if self.duplicates == 1 else "rows"
            out.append(f"{self.duplicates} {rows} repeating the previous row exactly (time and values) dropped.")
        if self.resampled:
            out.append(
                f"time steps jitter by {self.median_jitter:.1%} (median) and {self.max_jitter:.1%} (max) of the "
                f"median step {self.step:.6g} s: resampled by {INTERPOLATION} interpolation onto a uniform "
                f"{1 / self.step:.6g} Hz grid ({self.rows_after} samples)."
            )
        return tuple(out)


class TimeProblem(ValueError):
    """A time column that cannot be used: `index` is the 0-based row at fault, `problem` says why."""

    def __init__(self, problem: str, index: int):
        super().__init__(problem)
        self.problem = problem
        self.index = index


def check_times(t: np.ndarray, columns: dict, *, uniform: bool) -> tuple[dict, TimeCheck]:
    """Check time order (and, if `uniform` is needed, gaps); drop exact repeats; resample jitter when `uniform`.

    `columns` maps names to (N,) arrays including "t"; returns the columns to
    use (new arrays only when rows were dropped or resampled) and the TimeCheck.
    Raises TimeProblem naming the row of the first backwards step, repeated
    stamp with other values, or (when `uniform`) gap.
    """
    t = np.asarray(t, dtype=float)
    count = len(t)
    steps = np.diff(t)
    repeats = steps[:0].astype(np.intp)
    rows = None  # original row of each kept row, for messages; None while no row was dropped
    # One pass (the least step) tells an ordered log without repeats, almost every log, from the rest.
    if len(steps) and not steps.min() > 0:
        backwards = np.flatnonzero(steps < 0)
        if len(backwards):
            i = int(backwards[0]) + 1
            raise TimeProblem(f"time runs backwards: t = {t[i]:.9g} s after {t[i - 1]:.9g} s on the previous row", i)
        repeats = np.flatnonzero(steps == 0)
        names = [n for n in columns if n != "t"]
        same = np.ones(len(repeats), dtype=bool)
        for name in names:
            values = columns[name]
            same &= values[repeats + 1] == values[repeats]
        if not same.all():
            i = int(repeats[~same][0]) + 1
            raise TimeProblem(
                f"time stamp t = {t[i]:.9g} s repeats with other values than the previous row; "
                "duplicated stamps cannot be ordered", i,
            )
        keep = np.ones(count, dtype=bool)
        keep[repeats + 1] = False
        columns = {name: values[keep] for name, values in columns.items()}
        rows = np.flatnonzero(keep)
        t = columns["t"]
        steps = np.diff(t)
    if len(steps) == 0:
        return columns, TimeCheck(None, 0.0, 0.0, len(repeats), False, count, len(t))
    # One scratch array serves both medians and the deviations: every fresh million-sample temporary costs
    # page faults in a new process.
    scratch = steps.copy()
    step = median_in_place(scratch)
    deviation = np.abs(np.subtract(steps, step, out=scratch), out=scratch)
    deviation /= step
    max_jitter = float(deviation.max())
    median_jitter = median_in_place(deviation)  # after the max: it may reorder
    resampled = False
    if uniform:
        gaps = np.flatnonzero(steps > GAP_FACTOR * step)
        if len(gaps):
            i = int(gaps[0]) + 1
            raise TimeProblem(
                f"gap in time: {steps[i - 1]:.6g} s between t = {t[i - 1]:.9g} s and {t[i]:.9g} s, more than "
                f"{GAP_FACTOR:g} times the median step {step:.6g} s; derivatives cannot be estimated across it "
                "(fit the pieces as separate logs)",
                i if rows is None else int(rows[i]),
            )
        if max_jitter > UNIFORM_TOLERANCE:
            columns = resample(columns, step)
            resampled = True
    check = TimeCheck(step, median_jitter, max_jitter, len(repeats), resampled, count, len(columns["t"]))
    return columns, check


SAMPLED_MEDIAN_MIN = 16384
"""Arrays at least this long have their median found from a sample first (see median_in_place)."""

MEDIAN_SAMPLE = 4096
"""About this many evenly spaced values make that sample."""


def median_in_place(values: np.ndarray) -> float:
    """np.median of a 1-D float array without NaN; the array may be reordered.

    A long array's middle values are first bracketed by two values of an evenly
    spaced sample of it: two counting passes confirm that the middle ranks fall
    between them, and only the values in that bracket (a few per cent) are
    partitioned. This is exact whatever the sample shows: when the counts do not
    confirm the bracket (a sample that happens to miss the middle), or for a short
    array, the whole array is partitioned once, which reorders it. For an even
    count the two middle values' mean is taken as np.median takes it.
    """
    count = len(values)
    middle = count // 2
    lower_rank = middle - 1 if count % 2 == 0 else middle
    found = _bracketed_middle(values, lower_rank, middle) if count >= SAMPLED_MEDIAN_MIN else None
    if found is None:
        values.partition(middle)
        upper = values[middle]
        lower = values[:middle].max() if lower_rank < middle else upper
        found = lower, upper
    lower, upper = found
    return float(upper) if count % 2 else float((lower + upper) / 2)


def _bracketed_middle(values: np.ndarray, lower_rank: int, upper_rank: int) -> tuple[float, float] | None:
    """(the values of 0-based sorted ranks `lower_rank` and `upper_rank`), found between two sample values, or
    None when the sample's bracket does not hold both ranks."""
    count = len(values)
    sample = np.sort(values[:: count // MEDIAN_SAMPLE])
    # Six standard deviations of a sample quantile's rank either side: a random order misses once in 10^9.
    centre = len(sample) * upper_rank // count
    margin = 3 * int(np.sqrt(len(sample)))
    low, high = sample[max(centre - margin, 0)], sample[min(centre + margin, len(sample) - 1)]
    below = int(np.count_nonzero(values < low))
    at_most = int(np.count_nonzero(values <= high))
    if not below <= lower_rank <= upper_rank < at_most:
        return None
    if low == high:  # every value in the bracket is the same: a log's steps, often
        return low, low
    inside = values[(values >= low) & (values <= high)]
    ranks = sorted({lower_rank - below, upper_rank - below})
    inside.partition(ranks)
    return inside[lower_rank - below], inside[upper_rank - below]


def uniform_grid(start: float, end: float, step: float) -> np.ndarray:
    """Times start, start + step, ... up to end (within a millionth of a step), as start + k*step."""
    count = int(np.floor((end - start) / step * (1 + 1e-12) + 1e-6)) + 1
    return start + step * np.arange(count)


def resample(columns: dict, step: float) -> dict:
    """Every column interpolated by a not-a-knot cubic spline onto a uniform grid of `step` from the first time."""
    from scipy.interpolate import CubicSpline  # lazily: only jittered logs pay for the import

    t = columns["t"]
    grid = uniform_grid(float(t[0]), float(t[-1]), step)
    grid = grid[grid <= t[-1]]
    names = [n for n in columns if n != "t"]
    values = np.column_stack([columns[n] for n in names])
    spline = CubicSpline(t, values, axis=0)
    resampled = spline(grid)
    out = {"t": grid}
    out.update({name: np.ascontiguousarray(resampled[:, j]) for j, name in enumerate(names)})
    return out
