"""Logs as robots record them, in closed form and independent of jointid: the lesson's joint sampled at jittered
instants, angles quantised to 4096 counts a turn, Gaussian torque noise (see tests/core/logs/test_robot_logs.py)."""

from __future__ import annotations

import numpy as np

G = 9.81
TRUE = {"I": 0.8, "h": 0.4, "B": 0.15}
DURATION = 20.0
"""Seconds of motion (the real logs of the issue were about 20 s long)."""


def robot_log(rate: float, *, duration: float = DURATION, jitter: float = 0.10, counts: int = 4096,
              noise_share: float = 0.10, seed: int = 1) -> dict[str, np.ndarray]:
    """t, q, tau as a robot at `rate` Hz records the lesson's joint (see the module docstring)."""
    rng = np.random.default_rng(seed)
    count = int(round(duration * rate)) + 1
    t = (np.arange(count) + rng.uniform(-jitter, jitter, count)) / rate
    t[0] = 0.0
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)
    qd = 0.7 * 1.3 * np.cos(1.3 * t) + 0.25 * 2.7 * np.cos(2.7 * t)
    qdd = -0.7 * 1.3**2 * np.sin(1.3 * t) - 0.25 * 2.7**2 * np.sin(2.7 * t)
    tau = TRUE["I"] * qdd + TRUE["h"] * G * np.cos(q) + TRUE["B"] * qd
    tau = tau + rng.normal(0.0, noise_share * np.sqrt(np.mean(tau**2)), count)
    step = 2 * np.pi / counts
    return {"t": t, "q": np.round(q / step) * step, "tau": tau}


def write_log(path, columns: dict[str, np.ndarray]):
    """A CSV of the columns, every number float-round-tripped."""
    names = list(columns)
    lines = [",".join(names)]
    lines += [",".join(repr(float(v)) for v in row) for row in zip(*(columns[n] for n in names))]
    path.write_text("\n".join(lines) + "\n")
    return path
