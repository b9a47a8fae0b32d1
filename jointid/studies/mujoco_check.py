"""`jointid export --check`: load the written MJCF in MuJoCo and read back the joint's inertia and gravity torque.

MuJoCo is an optional extra (`jointid[mujoco]`), imported only here and only
when asked; the export itself never needs it. The check holds the joint at
rest where the centre of mass is level with the axis, so MuJoCo's torque to
hold it is the whole h g, and its mass matrix there is the joint's inertia I
(armature included).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..model.rigid_link import RigidLink
from ..model.terms import G

EXTRA_HINT = "--check loads the model in MuJoCo, which is optional: pip install 'jointid[mujoco]'"
"""The one line shown when mujoco is not installed."""

AGREEMENT = 1e-9
"""Relative difference below which MuJoCo's numbers are the identified ones (they differ by rounding only)."""


class MujocoMissing(ImportError):
    """The mujoco package is not installed; str() is EXTRA_HINT."""


@dataclass(frozen=True)
class MujocoCheck:
    """What MuJoCo makes of an exported model."""

    version: str
    """MuJoCo's version."""
    joint_inertia: float
    """The joint's mass matrix at rest (kg m²), armature included."""
    gravity_torque: float
    """MuJoCo's torque to hold the link at rest with its centre of mass level with the axis (N m), h g."""
    expected_inertia: float
    """The identified I."""
    expected_torque: float
    """The identified h g."""

    @property
    def agrees(self) -> bool:
        """Whether both numbers are the identified ones within AGREEMENT."""
        return all(math.isclose(value, expected, rel_tol=AGREEMENT, abs_tol=1e-300) for value, expected in
                   ((self.joint_inertia, self.expected_inertia), (self.gravity_torque, self.expected_torque)))


def import_mujoco():
    """The mujoco module; MujocoMissing when it is not installed."""
    try:
        import mujoco
    except ImportError:
        raise MujocoMissing(EXTRA_HINT) from None
    return mujoco


def check_mujoco(path: str, link: RigidLink) -> MujocoCheck:
    """Load the MJCF at `path` and read its joint inertia and its largest gravity torque (ValueError naming
    MuJoCo's complaint when it refuses the file)."""
    import numpy as np

    mujoco = import_mujoco()
    try:
        model = mujoco.MjModel.from_xml_path(str(path))
    except ValueError as error:
        raise ValueError(f"MuJoCo refuses {path}: {' '.join(str(error).split())}") from None
    data = mujoco.MjData(model)
    # The centre of mass's direction turns with the joint as axis_sign says: level (along +x) at this value.
    data.qpos[0] = -link.axis_sign * link.com_angle
    mujoco.mj_forward(model, data)
    inertia = np.zeros(1)
    mujoco.mj_mulM(model, data, inertia, np.ones(1))
    torque = abs(float(data.qfrc_bias[0]))
    return MujocoCheck(mujoco.__version__, float(inertia[0]), torque, link.joint_inertia, link.mass_moment * G)
