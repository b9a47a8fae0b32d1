"""A live session's time, kept growing across stretches: after a reconnection or a file replaced, the source's own
clock may start again from zero (a robot rebooted), and one session's samples must still follow each other."""

from __future__ import annotations

import numpy as np

MIN_GAP = 1.0
"""Seconds put between two stretches when the second's clock started again (and no wall-clock gap is known)."""


class StretchClock:
    """Times of a session's samples: each stretch on its own clock, shifted when that clock starts again, so
    that time never runs backwards across a break."""

    def __init__(self):
        self.last: float | None = None
        self.shift = 0.0
        self.pending_gap: float | None = None

    def new_stretch(self, gap: float | None = None) -> None:
        """The next sample starts a new stretch, `gap` seconds (wall clock) after the last one, when known."""
        self.pending_gap = MIN_GAP if gap is None else max(float(gap), 0.0)

    @property
    def starting(self) -> bool:
        """True while the next sample starts a new stretch."""
        return self.pending_gap is not None

    def place(self, t: np.ndarray) -> tuple[np.ndarray, str | None]:
        """The times `t` (increasing, on the source's clock) on the session's time, and a sentence when a new
        stretch's clock started again and was shifted (None otherwise)."""
        said = None
        if len(t) and self.pending_gap is not None:
            first = float(t[0]) + self.shift
            if self.last is not None and first <= self.last:
                self.shift += self.last + max(self.pending_gap, MIN_GAP) - first
                said = (f"the source's clock started again (t = {float(t[0]):.6g} s after {self.last:.6g} s): its "
                        f"times are shifted by {self.shift:.6g} s to follow on")
            self.pending_gap = None
        placed = t + self.shift if self.shift else t
        if len(placed):
            self.last = float(placed[-1])
        return placed, said
