"""The synthetic Coulomb joint of issue 23's acceptance: a log as a dict of arrays, with pushes where asked."""

from __future__ import annotations

import numpy as np

G = 9.81


def coulomb_joint_log(seed: int, pushes=()):
    """The lesson's rich motion on a joint with Coulomb friction 0.2 N m, 20 s at 500 Hz, 12-bit angles, torque
    noise 5 % of its RMS; each push a smooth bump of 1 N m (raised cosine) from an outside hand, which the log's
    torque does not see (the motor needs that much less)."""
    rng = np.random.default_rng(seed)
    t = np.arange(0, 20, 1 / 500)
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)
    qd = 0.7 * 1.3 * np.cos(1.3 * t) + 0.25 * 2.7 * np.cos(2.7 * t)
    qdd = -0.7 * 1.69 * np.sin(1.3 * t) - 0.25 * 7.29 * np.sin(2.7 * t)
    tau = 0.8 * qdd + 0.4 * G * np.cos(q) + 0.15 * qd + 0.2 * np.sign(qd)
    tau = tau + 0.05 * np.sqrt(np.mean(tau**2)) * rng.standard_normal(len(t))
    for start, length, size in pushes:
        inside = (t >= start) & (t <= start + length)
        tau[inside] -= size * 0.5 * (1 - np.cos(2 * np.pi * (t[inside] - start) / length))
    step = 2 * np.pi / 4096
    return {"t": t, "q": np.round(q / step) * step, "tau": tau}
