"""A closed-form joint logged in a robot's conventions, for the tests of column names and angle conventions.

The joint follows a rich swing (plus an optional steady spin) with I = 0.8, h = 0.4, B = 0.15 and g = 9.81
in jointid's convention; `logged` writes it as a robot with another convention would (angle
a = s (q - offset), torque positive toward increasing a), computed here with numpy, not with jointid's code.
"""

from __future__ import annotations

import numpy as np

G = 9.81
TRUE = np.array([0.8, 0.4, 0.15])
OFFSETS = {"right": 0.0, "up": np.pi / 2, "left": np.pi, "down": -np.pi / 2}


def joint(t, spin: float = 0.0):
    """q, qd, qdd (jointid's convention) and tau of the closed-form joint: a rich swing plus `spin` rad/s."""
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t) + spin * t
    qd = 0.7 * 1.3 * np.cos(1.3 * t) + 0.25 * 2.7 * np.cos(2.7 * t) + spin
    qdd = -0.7 * 1.3**2 * np.sin(1.3 * t) - 0.25 * 2.7**2 * np.sin(2.7 * t)
    tau = TRUE[0] * qdd + TRUE[1] * G * np.cos(q) + TRUE[2] * qd
    return q, qd, qdd, tau


def logged(t, zero="right", clockwise=False, spin=0.0):
    """The joint as a robot with another convention logs it: (angle, velocity, acceleration, torque)."""
    q, qd, qdd, tau = joint(t, spin)
    s = -1.0 if clockwise else 1.0
    # q = s a + offset, so a = s (q - offset); a torque positive toward increasing a is s tau.
    return s * (q - OFFSETS[zero]), s * qd, s * qdd, s * tau


def lstsq(q, qd, qdd, tau):
    """numpy's least-squares I, h, B of the true columns."""
    return np.linalg.lstsq(np.column_stack([qdd, G * np.cos(q), qd]), tau, rcond=None)[0]


def wrap(angle, period=2 * np.pi, positive=False):
    """The angle wrapped to (-period/2, period/2] or [0, period), as a driver reports it."""
    wrapped = np.mod(angle, period)
    return wrapped if positive else np.where(wrapped > period / 2, wrapped - period, wrapped)
