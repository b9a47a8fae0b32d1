"""Prescribed joint motions with analytic velocity and acceleration.

Each motion is a sum of sinusoids q(t) = sum a*sin(w*t + phase), so its
derivatives are exact and every sample is a realisable kinematic state.
"""

from __future__ import annotations

from dataclasses import dataclass
from math import pi

import numpy as np

from ..options import DURATION, VALIDATION_MOTION_NAME


@dataclass(frozen=True)
class SineTerm:
    """One term a*sin(w*t + phase) of a motion's angle (rad, rad/s, rad)."""

    amplitude: float
    frequency: float
    phase: float = 0.0


@dataclass(frozen=True, eq=False)
class JointStates:
    """Joint angle, velocity and acceleration at sample times; every array has shape (N,)."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray


@dataclass(frozen=True)
class Motion:
    """A named prescribed motion q(t) built from sine terms (no terms: a hold at q = 0)."""

    name: str
    label: str
    terms: tuple[SineTerm, ...]

    def states(self, t) -> JointStates:
        """Evaluate q, qd, qdd analytically at times t (s), shape (N,)."""
        t = np.asarray(t, dtype=float)
        q, qd, qdd = (np.zeros_like(t) for _ in range(3))
        for term in self.terms:
            angle = term.frequency * t + term.phase
            q += term.amplitude * np.sin(angle)
            qd += term.amplitude * term.frequency * np.cos(angle)
            qdd -= term.amplitude * term.frequency**2 * np.sin(angle)
        return JointStates(t=t, q=q, qd=qd, qdd=qdd)


TRAINING_MOTIONS = {
    "rich": Motion("rich", "Rich motion", (SineTerm(0.7, 1.3), SineTerm(0.25, 2.7))),
    "slow": Motion("slow", "Slow motion", (SineTerm(0.08, 0.4),)),
    "holds": Motion("holds", "Horizontal holds", ()),
}
"""The training motions the lab offers, by name."""

VALIDATION_MOTION = Motion(
    VALIDATION_MOTION_NAME, "Validation motion", (SineTerm(0.6, 0.9), SineTerm(0.3, 2.1, pi / 2))
)
"""q_test(t) = 0.6 sin(0.9 t) + 0.3 cos(2.1 t), never used for fitting."""

ALL_MOTIONS = {**TRAINING_MOTIONS, VALIDATION_MOTION.name: VALIDATION_MOTION}
"""Every motion by name, the validation motion included."""


def sample_times(count: int) -> np.ndarray:
    """Times t_i = DURATION*i/(count-1), i = 0..count-1, shape (count,)."""
    return np.linspace(0.0, DURATION, count)
