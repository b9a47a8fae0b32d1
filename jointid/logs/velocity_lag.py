"""How far a logged velocity lags the derivative of the logged position: a motor controller's velocity is the
position's change averaged over a window (a SPARK MAX: 32 ms deltas, eight deep), so it trails the motion.

Both are put on one uniform grid per test run (the median sample step), the position's derivative taken from
consecutive samples at their midpoints; the lag is the shift of the velocity that best matches the derivative,
the peak of their cross-correlation over all runs, computed as the least mean squared difference over the
overlap (plain products would favour a ramp's larger end, and a quasistatic test is a ramp), refined between
grid steps by a parabola through the peak and its two neighbours.
"""

from __future__ import annotations

import numpy as np

MAX_LAG_S = 0.5
"""The longest lag looked for (s): well beyond a SPARK MAX's 0.1-0.3 s, well inside a test."""

MIN_SAMPLES = 8
"""A run shorter than this adds nothing to the correlation."""


def velocity_lag(t: np.ndarray, q: np.ndarray, qd: np.ndarray, segments: list[slice]) -> float | None:
    """Seconds the logged velocity `qd` trails the derivative of `q` (positive: behind), over the samples of
    `segments` (one per test run, times `t` in s); None when too little moves to tell."""
    steps = np.concatenate([np.diff(t[rows]) for rows in segments]) if segments else np.array([])
    steps = steps[steps > 0]
    if len(steps) < MIN_SAMPLES:
        return None
    step = float(np.median(steps))
    most = max(1, int(MAX_LAG_S / step))
    pairs = []
    for rows in segments:
        times, position, velocity = t[rows], q[rows], qd[rows]
        if len(times) < MIN_SAMPLES or not np.all(np.diff(times) > 0):
            continue
        middles = 0.5 * (times[1:] + times[:-1])
        derivative = np.diff(position) / np.diff(times)
        grid = np.arange(middles[0], middles[-1], step)
        if len(grid) <= 2 * most:
            continue
        pairs.append((np.interp(grid, middles, derivative), np.interp(grid, times, velocity)))
    if not pairs:
        return None
    lags = np.arange(-most, most + 1)
    misfit = np.array([_mean_squared_difference(pairs, int(lag)) for lag in lags])
    best = int(np.argmin(misfit))
    if best in (0, len(lags) - 1) or not np.isfinite(misfit[best]):
        return None  # the best shift is at the end of the search: no lag this method can state
    before, at, after = misfit[best - 1], misfit[best], misfit[best + 1]
    curve = before - 2 * at + after
    shift = 0.0 if curve <= 0 else 0.5 * (before - after) / curve
    return float((lags[best] + shift) * step)


def _mean_squared_difference(pairs, lag: int) -> float:
    """Mean of (velocity[n + lag] - derivative[n])^2 over every run's overlapping samples."""
    total, count = 0.0, 0
    for derivative, velocity in pairs:
        if lag >= 0:
            a, b = derivative[: len(derivative) - lag], velocity[lag:]
        else:
            a, b = derivative[-lag:], velocity[: len(velocity) + lag]
        total += float(np.sum((b - a) ** 2))
        count += len(a)
    return total / count if count else np.inf


def lag_note(entry: str, lag: float) -> str:
    """The sentence the fit's notes give about the logged velocity's lag (s)."""
    return (f"The logged velocity {entry!r} lags the position's derivative by {lag * 1e3:.0f} ms (cross-correlation "
            "over the tests): the fit takes its speed from the position, not from this velocity"
            + (". SysId's analysis takes the logged velocity, so its kA differs where this lag is large (a SPARK MAX "
               "averages position changes over 32 ms, eight deep)." if abs(lag) >= NOTABLE_LAG_S else "."))


NOTABLE_LAG_S = 0.01
"""A lag from which the note explains what it does to SysId's kA (a 50 Hz loop's half step)."""
