"""Simulated joints for live identification, in plain numpy (not jointid's code): an arm driven through a rich
motion with torque measured, and a flywheel driven by a varied voltage; each sampled as a source would hand it
over, in blocks."""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

G = 9.81

ARM_TRUTH = {"I": 0.05, "h": 0.3, "B": 0.1, "Fc": 0.2, "tau0": 0.2}
"""The arm's inertia (kg m^2), mass moment (kg m), damping (N m s/rad), Coulomb friction and torque bias (N m)."""

FLYWHEEL_TRUTH = {"kA": 0.02, "kV": 0.12, "kS": 0.3}
"""The flywheel's WPILib SimpleMotorFeedforward gains per radian: kA (V s^2/rad), kV (V s/rad), kS (V)."""


@dataclass(frozen=True)
class Samples:
    """A simulated log: times, angle, effort, and the truth."""

    t: np.ndarray
    q: np.ndarray
    tau: np.ndarray
    truth: dict

    def blocks(self, size: int):
        """The samples in blocks of `size`, as a live source's poll returns them: column dicts."""
        for first in range(0, len(self.t), size):
            yield {"t": self.t[first:first + size], "q": self.q[first:first + size],
                   "tau": self.tau[first:first + size]}


def arm(rate: float, seconds: float, noise: float = 0.05, seed: int = 1, jitter: float = 0.0,
        bias: float = ARM_TRUTH["tau0"]) -> Samples:
    """An arm swung by a sum of three sines (0.3, 0.7, 1.3 Hz) with its torque measured with Gaussian noise; each
    sample taken up to `jitter` periods early or late (uniformly), as a robot loop's; `bias` the torque bias."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(round(seconds * rate))) / rate
    if jitter:
        t = t + jitter / rate * rng.uniform(-1, 1, len(t))
    motion = [(0.8, 0.3, 0.0), (0.4, 0.7, 1.0), (0.2, 1.3, 2.0)]
    q = sum(a * np.sin(2 * np.pi * f * t + phase) for a, f, phase in motion)
    qd = sum(a * 2 * np.pi * f * np.cos(2 * np.pi * f * t + phase) for a, f, phase in motion)
    qdd = sum(-a * (2 * np.pi * f) ** 2 * np.sin(2 * np.pi * f * t + phase) for a, f, phase in motion)
    k = dict(ARM_TRUTH, tau0=bias)
    tau = (k["I"] * qdd + k["h"] * G * np.cos(q) + k["B"] * qd + k["Fc"] * np.sign(qd) + k["tau0"]
           + noise * rng.standard_normal(len(t)))
    return Samples(t, q, tau, k)


@lru_cache(maxsize=8)
def flywheel(rate: float, seconds: float, noise: float = 0.02, seed: int = 2) -> Samples:
    """A flywheel driven by a varied voltage (two sines and a square wave), kA a = V - kS sgn v - kV v integrated by
    fourth-order Runge-Kutta at 1 ms, its angle read at `rate` and its voltage logged with Gaussian noise."""
    rng = np.random.default_rng(seed)
    k = FLYWHEEL_TRUTH
    fine = 1e-3
    count = int(round(seconds / fine)) + 1
    times = np.arange(count) * fine

    def volts(time):
        """The voltage applied at `time`."""
        return 4.0 * np.sin(2 * np.pi * 0.25 * time) + 2.0 * np.sin(2 * np.pi * 1.7 * time) + \
            1.5 * np.sign(np.sin(2 * np.pi * 0.9 * time))

    def acceleration(time, v):
        """The flywheel's acceleration at `time` and speed `v`."""
        return (volts(time) - k["kS"] * np.sign(v) - k["kV"] * v) / k["kA"]

    v = np.empty(count)
    x = np.empty(count)
    v[0] = x[0] = 0.0
    for n in range(count - 1):
        time, speed = times[n], v[n]
        a1 = acceleration(time, speed)
        a2 = acceleration(time + fine / 2, speed + fine / 2 * a1)
        a3 = acceleration(time + fine / 2, speed + fine / 2 * a2)
        a4 = acceleration(time + fine, speed + fine * a3)
        v[n + 1] = speed + fine / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
        x[n + 1] = x[n] + fine / 2 * (speed + v[n + 1])
    every = int(round(1 / (rate * fine)))
    t, q = times[::every], x[::every]
    tau = volts(t) + noise * rng.standard_normal(len(t))
    return Samples(t, q, tau, dict(k))
