"""An independent numpy model of the synthetic joint and its data, for the missing-physics tests.

Written from the issue's definitions (motion formulas, the lesson's LCG, the
true joint's physics), not from jointid's code.
"""

from __future__ import annotations

import numpy as np

G = 9.81
MODULUS = 2**32
TRUE = {"I": 0.8, "h": 0.4, "B": 0.15}


def rich_states(samples: int):
    """q_true, qd, qdd of q = 0.7 sin(1.3 t) + 0.25 sin(2.7 t) at t_i = 8 i/(N-1)."""
    t = np.linspace(0.0, 8.0, samples)
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)
    qd = 0.7 * 1.3 * np.cos(1.3 * t) + 0.25 * 2.7 * np.cos(2.7 * t)
    qdd = -0.7 * 1.3**2 * np.sin(1.3 * t) - 0.25 * 2.7**2 * np.sin(2.7 * t)
    return t, q, qd, qdd


def validation_states():
    """The 16 held-out states of q = 0.6 sin(0.9 t) + 0.3 cos(2.1 t)."""
    t = np.linspace(0.0, 8.0, 16)
    q = 0.6 * np.sin(0.9 * t) + 0.3 * np.cos(2.1 * t)
    qd = 0.6 * 0.9 * np.cos(0.9 * t) - 0.3 * 2.1 * np.sin(2.1 * t)
    qdd = -0.6 * 0.9**2 * np.sin(0.9 * t) - 0.3 * 2.1**2 * np.cos(2.1 * t)
    return t, q, qd, qdd


def noise(bound: float, samples: int, seeds) -> np.ndarray:
    """(len(seeds), samples) The lesson's LCG noise, one row per seed, drawn sample by sample."""
    state = np.array(seeds, dtype=np.uint64).reshape(-1)
    rows = np.empty((state.size, samples))
    for i in range(samples):
        state = (np.uint64(1664525) * state + np.uint64(1013904223)) % np.uint64(MODULUS)
        rows[:, i] = bound * (2 * state.astype(float) / MODULUS - 1)
    return rows


def measured(q_true, qd, qdd, coulomb=0.0, bias=0.0):
    """What the torque sensor reads for the true joint with its missing physics."""
    return TRUE["I"] * qdd + TRUE["h"] * G * np.cos(q_true) + TRUE["B"] * qd + coulomb * np.sign(qd) + bias


COLUMNS = {
    "I": lambda q, qd, qdd: qdd,
    "h": lambda q, qd, qdd: G * np.cos(q),
    "B": lambda q, qd, qdd: qd,
    "Fc": lambda q, qd, qdd: np.sign(qd),
    "tau0": lambda q, qd, qdd: np.ones_like(q),
    "h_s": lambda q, qd, qdd: G * np.sin(q),
}
MODELS = {
    "plain": ("I", "h", "B"),
    "coulomb": ("I", "h", "B", "Fc"),
    "bias": ("I", "h", "B", "tau0"),
    "angle-offset": ("I", "h", "B", "h_s"),
    "coulomb+bias": ("I", "h", "B", "Fc", "tau0"),
    "coulomb+angle-offset": ("I", "h", "B", "Fc", "h_s"),
}


def regressor(model: str, q, qd, qdd) -> np.ndarray:
    """(N, p) The model's columns, by hand."""
    return np.column_stack([COLUMNS[name](q, qd, qdd) for name in MODELS[model]])


def bic(model: str, q, qd, qdd, tau) -> np.ndarray:
    """BIC = N ln(RSS/N) + k ln N of the model's lstsq fit, per column of tau (N,) or (N, K)."""
    X = regressor(model, q, qd, qdd)
    theta = np.linalg.lstsq(X, tau, rcond=None)[0]
    rss = np.sum((tau - X @ theta) ** 2, axis=0)
    n, k = X.shape
    return n * np.log(rss / n) + k * np.log(n)
