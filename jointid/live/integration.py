"""A position from a velocity topic when no position is published, as a data log's routine without a position
entry is read (jointid.logs.wpilog): the velocity integrated by trapezoids, within a stretch."""

from __future__ import annotations

import numpy as np


class VelocityIntegral:
    """q integrated from qd block after block; a new stretch starts again from 0."""

    def __init__(self):
        self.last: tuple[float, float, float] | None = None  # (t, qd, q) of the last sample

    def restart(self) -> None:
        """A new stretch: nothing is integrated across the gap."""
        self.last = None

    def position(self, t: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """(N,) q at the times `t` from the velocities `qd`, continuing the last block's."""
        if not len(t):
            return np.zeros(0)
        start_t, start_qd, start_q = self.last if self.last is not None else (t[0], qd[0], 0.0)
        times = np.concatenate(([start_t], t))
        speeds = np.concatenate(([start_qd], qd))
        q = start_q + np.cumsum(0.5 * (speeds[1:] + speeds[:-1]) * np.diff(times))
        self.last = (float(t[-1]), float(qd[-1]), float(q[-1]))
        return q
