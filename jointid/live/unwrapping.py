"""A wrapped angle made continuous as it arrives, as a recorded log's is (jointid.logs.angles): a step within a
quarter turn of a full turn between two samples is the angle passing the encoder's seam, never the joint's own
motion, so it is undone; differentiating across it would invent a huge speed."""

from __future__ import annotations

import math

import numpy as np

TURN = 2 * math.pi
"""A full turn in radians (the sources convert to radians before unwrapping)."""


class LiveUnwrap:
    """Undoes the wraps of q block after block, within a stretch."""

    def __init__(self):
        self.last: float | None = None
        self.turns = 0.0  # radians added to every later sample
        self.said = False

    def restart(self) -> None:
        """A new stretch: its angle is its own."""
        self.last, self.turns = None, 0.0

    def unwrap(self, t: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, str | None]:
        """(q with its wraps undone, a sentence the first time one is undone, else None)."""
        if not len(q):
            return q, None
        previous = q[0] if self.last is None else self.last
        steps = np.diff(q, prepend=previous)
        wraps = np.abs(np.abs(steps) - TURN) <= TURN / 4
        self.last = float(q[-1])
        if not wraps.any():
            return (q + self.turns if self.turns else q), None
        added = self.turns - TURN * np.cumsum(np.where(wraps, np.round(steps / TURN), 0.0))
        self.turns = float(added[-1])
        said = None
        if not self.said:
            first = int(np.flatnonzero(wraps)[0])
            said = (f"q jumped by nearly a full turn at t = {float(t[first]):.6g} s: the angle is wrapped, and is "
                    "unwrapped as it arrives (numpy.unwrap's rule)")
            self.said = True
        return q + added, said
