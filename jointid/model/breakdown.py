"""The plain model's inverse dynamics split into its contributions (the `jointid torque` readout).

Kept out of jointid.model.terms so that a fit's start-up does not build this class
(jointid.model.terms still offers both names).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..checks import checked, real_array
from .terms import TRUE_PARAMETERS, G


@dataclass(frozen=True, eq=False)
class TorqueBreakdown:
    """Inverse dynamics of the plain model at given states, split into its three contributions.

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


def _three(value, where: str):
    """The checks' rule for theta: [I, h, B], three finite numbers."""
    values = real_array(1)(value, where)
    if len(values) != 3:
        raise ValueError(f"{where} must be [I, h, B], three numbers; got {len(values)}")
    return values


@checked(q=real_array(), qd=real_array(), qdd=real_array(), theta=_three)
def torque_breakdown(q, qd, qdd, theta=TRUE_PARAMETERS) -> TorqueBreakdown:
    """The plain model's torque split into its contributions (what `jointid torque` prints).

    Parameters
    ----------
    q, qd, qdd : array_like
        Angle (rad), velocity (rad/s) and acceleration (rad/s^2); broadcast together.
    theta : array_like
        [I, h, B] (default the lesson's joint).

    Returns
    -------
    TorqueBreakdown
        The inertia, gravity and damping torques, their total and the damper's power.
    """
    inertia, mass_moment, damping = (float(v) for v in theta)
    q, qd, qdd = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (q, qd, qdd)))
    return TorqueBreakdown(
        inertia=inertia * qdd,
        gravity=mass_moment * G * np.cos(q),
        damping=damping * qd,
        damper_power=damping * qd**2,
    )
