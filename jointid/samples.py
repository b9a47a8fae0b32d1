"""Joint data: states and torque at N instants, synthetic or from a log."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .norms import all_finite, rms


STATES = ("q", "qd", "qdd", "tau")
"""The columns every sample needs; t is optional."""


@dataclass(frozen=True, eq=False)
class JointData:
    """Angle q (rad), velocity qd (rad/s), acceleration qdd (rad/s^2) and torque tau (N m).

    Every array has shape (N,); `t` (s) is None when the source had no times.
    """

    t: np.ndarray | None
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    tau: np.ndarray

    def __post_init__(self):
        missing = [name for name in STATES if getattr(self, name) is None]
        if missing:
            raise ValueError(f"JointData needs {' and '.join(missing)}; jointid.fit_log estimates qd and qdd "
                             "from q and t")
        length = None
        for name in (*STATES, "t"):
            given = getattr(self, name)
            if given is None:
                continue
            values = np.asarray(given)
            if values.ndim != 1 or values.dtype.kind not in "biuf":
                raise ValueError(f"JointData's {name} must be a 1-D array of real numbers; got "
                                 f"{values.dtype} values of shape {values.shape}")
            if values.size and not all_finite(values):  # a NaN would reach the fit as a silent NaN estimate
                index = int(np.flatnonzero(~np.isfinite(values))[0])
                raise ValueError(f"JointData's {name} must be finite numbers; got {values[index]} at index {index}")
            if length is not None and len(values) != length:
                raise ValueError(f"JointData's {name} has {len(values)} values where q has {length}")
            length = len(values)
            object.__setattr__(self, name, values if values.dtype == float else values.astype(float))

    @property
    def count(self) -> int:
        """N, the number of samples."""
        return len(self.tau)

    @cached_property
    def accel_rms(self) -> float:
        """Root mean square of qdd (rad/s^2)."""
        return rms(self.qdd)

    @cached_property
    def speed_rms(self) -> float:
        """Root mean square of qd (rad/s)."""
        return rms(self.qd)

    @cached_property
    def time_axis(self) -> np.ndarray:
        """(N,) Times for plotting: `t` when known, else the sample index."""
        return self.t if self.t is not None else np.arange(self.count, dtype=float)
