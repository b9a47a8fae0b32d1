"""The synthetic joint the experiments measure: the lesson's joint plus optional missing physics.

Three effects the plain model cannot see, each zero by default so every lesson
number stays as it is:

- Coulomb friction FC: the joint adds FC*sign(qd) (sign(0) = 0);
- a torque sensor bias TAU0: the sensor reads TAU0 too much on every sample;
- an encoder offset Q0: the logged angle is q_true - Q0 while gravity acts on
  q_true. Motion formulas give q_true.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..options import TRUE_VALUES
from .terms import G


@dataclass(frozen=True)
class TrueJoint:
    """The joint behind synthetic data: I, h, B and the missing physics (all in SI units)."""

    inertia: float = TRUE_VALUES["I"]
    mass_moment: float = TRUE_VALUES["h"]
    damping: float = TRUE_VALUES["B"]
    coulomb: float = 0.0
    """FC (N m): friction torque FC*sign(qd) the actuator must also supply."""
    bias: float = 0.0
    """TAU0 (N m): what the torque sensor adds to every reading."""
    angle_offset: float = 0.0
    """Q0 (rad): the encoder's zero is off; logged q = q_true - Q0."""

    @property
    def has_missing_physics(self) -> bool:
        """True when any effect beyond the plain model is present."""
        return bool(self.coulomb or self.bias or self.angle_offset)

    def actuator_torque(self, q_true, qd, qdd) -> np.ndarray:
        """The torque the actuator applies (N m) at true states: I*qdd + h*g*cos(q_true) + B*qd + FC*sign(qd)."""
        # Plain arithmetic, not the regressor: it works on scalars too, cheaply (the simulation
        # check evaluates it at every integrator step), and the extras are added only when present.
        torque = self.inertia * qdd + self.mass_moment * G * np.cos(q_true) + self.damping * qd
        if self.coulomb:
            torque = torque + self.coulomb * np.sign(qd)
        return torque

    def measured_torque(self, q_true, qd, qdd) -> np.ndarray:
        """What the torque sensor reads (N m): the actuator torque plus the sensor bias."""
        torque = self.actuator_torque(q_true, qd, qdd)
        return torque + self.bias if self.bias else torque

    def logged_angle(self, q_true) -> np.ndarray:
        """What the encoder reports (rad): q_true - Q0."""
        q_true = np.asarray(q_true, dtype=float)
        return q_true - self.angle_offset if self.angle_offset else q_true

    def values_for(self, model) -> np.ndarray:
        """(p,) This joint's value of each of a model's reported parameters (a JointModel's `names`)."""
        values = {"I": self.inertia, "h": self.mass_moment, "B": self.damping, "Fc": self.coulomb,
                  "tau0": self.bias, "q0": self.angle_offset}
        return np.array([values[name] for name in model.names])

    def description(self) -> str:
        """The joint as one short line, naming only the effects present."""
        parts = [f"I = {self.inertia:g} kg m²", f"h = {self.mass_moment:g} kg m", f"B = {self.damping:g} N m s/rad"]
        if self.coulomb:
            parts.append(f"Coulomb friction {self.coulomb:g} N m")
        if self.bias:
            parts.append(f"sensor bias {self.bias:g} N m")
        if self.angle_offset:
            parts.append(f"encoder offset {self.angle_offset:g} rad")
        return ", ".join(parts)


LESSON_JOINT = TrueJoint()
"""The lesson's joint: I = 0.8, h = 0.4, B = 0.15 and nothing else."""
