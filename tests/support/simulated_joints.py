"""Joints simulated for the live-source tests: a prescribed motion and the effort that drives it, computed here in
closed form (the expected values of every live test, never taken from jointid)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

G = 9.81


@dataclass(frozen=True, eq=False)
class SimulatedRun:
    """Samples of a simulated joint: (N,) arrays t (s), q, qd, qdd, tau, and 'state' texts (or None)."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    tau: np.ndarray
    state: np.ndarray | None = None

    def columns(self) -> dict:
        """Name -> array, state included when there is one."""
        out = {"t": self.t, "q": self.q, "qd": self.qd, "qdd": self.qdd, "tau": self.tau}
        return out if self.state is None else {**out, "state": self.state}


def _motion(t: np.ndarray, terms) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """q, qd, qdd of a sum of sines (amplitude, angular frequency, phase)."""
    q, qd, qdd = np.zeros_like(t), np.zeros_like(t), np.zeros_like(t)
    for amplitude, frequency, phase in terms:
        angle = frequency * t + phase
        q += amplitude * np.sin(angle)
        qd += amplitude * frequency * np.cos(angle)
        qdd -= amplitude * frequency**2 * np.sin(angle)
    return q, qd, qdd


ARM = {"I": 0.8, "h": 0.4, "B": 0.15}
"""The simulated arm's inertia (kg m^2), gravity mass moment (kg m) and damping (N m s/rad)."""

ARM_MOTION = ((0.9, 1.3, 0.0), (0.4, 3.1, 0.7))
"""The arm's motion: a sum of sines rich in speed and acceleration."""


def arm(rate: float, duration: float, start: float = 0.0) -> SimulatedRun:
    """An arm swinging at `rate` Hz for `duration` s from t = `start`: tau = I qdd + h g cos q + B qd (N m)."""
    t = start + np.arange(int(round(duration * rate))) / rate
    q, qd, qdd = _motion(t, ARM_MOTION)
    tau = ARM["I"] * qdd + ARM["h"] * G * np.cos(q) + ARM["B"] * qd
    return SimulatedRun(t, q, qd, qdd, tau)


FLYWHEEL = {"kS": 0.2, "kV": 0.12, "kA": 0.03}
"""The simulated flywheel's gains: V = kS sgn(v) + kV v + kA a (volts, radians)."""


def flywheel(rate: float, duration: float, start: float = 0.0) -> SimulatedRun:
    """A flywheel (a simple motor) run back and forth at `rate` Hz: V = kS sgn(qd) + kV qd + kA qdd, with the
    SysId test under way named at each sample (forward while it speeds up one way, reverse the other)."""
    t = start + np.arange(int(round(duration * rate))) / rate
    q, qd, qdd = _motion(t, ((30.0, 0.8, 0.0), (6.0, 2.9, 0.3)))
    tau = FLYWHEEL["kS"] * np.sign(qd) + FLYWHEEL["kV"] * qd + FLYWHEEL["kA"] * qdd
    state = np.where(qd >= 0, "dynamic-forward", "dynamic-reverse").astype(object)
    return SimulatedRun(t, q, qd, qdd, tau, state)
