"""The one-joint torque model: tau = I*qdd + h*g*cos(q) + B*qd.

q is measured counter-clockwise from world +x (q = 0 points horizontally
right), gravity acts along world -y, and positive torque drives q upward.
The gravity and damping terms are *compensation* torques: the actuator
supplies them, so a horizontal hold needs tau = h*g.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

G = 9.81
"""Gravitational acceleration (m/s^2)."""

PARAMETER_NAMES = ("I", "h", "B")
"""Parameter order in theta and in every regressor row."""

PARAMETER_LABELS = {
    "I": "inertia",
    "h": "mass moment",
    "B": "damping",
}
"""Plain-language name of each parameter."""

PARAMETER_UNITS = {"I": "kg m²", "h": "kg m", "B": "N m s/rad"}
"""SI unit of each parameter."""

TRUE_PARAMETERS = np.array([0.8, 0.4, 0.15])
"""The synthetic joint's parameters [I, h, B]."""

SIGN_REQUIREMENTS = {"I": "I > 0", "h": "h ≥ 0", "B": "B ≥ 0"}
"""The sign each parameter must have in this joint model, as text."""


def regressor(q, qd, qdd) -> np.ndarray:
    """Stack regressor rows [qdd, g*cos(q), qd], shape (N, 3), for states of shape (N,)."""
    q, qd, qdd = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (q, qd, qdd)))
    # Column-major: each column is written contiguously, and the solver's
    # column-major working copy is then a straight scaled copy.
    rows = np.empty((q.size, 3), order="F")
    rows[:, 0] = qdd.ravel()
    np.multiply(G, np.cos(q.ravel()), out=rows[:, 1])
    rows[:, 2] = qd.ravel()
    return rows


def sign_failures(theta) -> tuple[str, ...]:
    """Names of the parameters in theta = [I, h, B] that break I > 0, h >= 0, B >= 0."""
    inertia, mass_moment, damping = (float(v) for v in theta)
    checks = {"I": inertia > 0, "h": mass_moment >= 0, "B": damping >= 0}
    return tuple(name for name, ok in checks.items() if not ok)


@dataclass(frozen=True, eq=False)
class TorqueBreakdown:
    """Inverse dynamics at given states, split into its three contributions.

    Every field has the shape of the broadcast states.
    """

    inertia: np.ndarray
    """I*qdd (N m)."""
    gravity: np.ndarray
    """h*g*cos(q), the gravity compensation (N m)."""
    damping: np.ndarray
    """B*qd, the damping compensation (N m)."""
    damper_power: np.ndarray
    """B*qd^2, mechanical power the damper dissipates (W)."""

    @property
    def total(self) -> np.ndarray:
        """Actuator torque I*qdd + h*g*cos(q) + B*qd (N m)."""
        return self.inertia + self.gravity + self.damping


def torque_breakdown(q, qd, qdd, theta=TRUE_PARAMETERS) -> TorqueBreakdown:
    """Compute the actuator torque's contributions at states (q, qd, qdd) for theta = [I, h, B]."""
    inertia, mass_moment, damping = (float(v) for v in theta)
    q, qd, qdd = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (q, qd, qdd)))
    return TorqueBreakdown(
        inertia=inertia * qdd,
        gravity=mass_moment * G * np.cos(q),
        damping=damping * qd,
        damper_power=damping * qd**2,
    )


def predict_torque(q, qd, qdd, theta=TRUE_PARAMETERS) -> np.ndarray:
    """Actuator torque (N m) at states (q, qd, qdd) for theta = [I, h, B]."""
    return regressor(q, qd, qdd) @ np.asarray(theta, dtype=float)
