"""The settings of a synthetic experiment: one frozen object of every setting, checked on creation.

Motion, noise, samples and seed describe the lesson's experiment; `model`
names the fitted model; the `true_*` settings add physics the plain model
cannot see to the synthetic joint (all zero by default). No numpy here: the
command line parses settings before it loads the numeric modules (and uses
`jointid.options`, which this module re-exports, to build its parser).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..options import (
    FIELDS,
    SETTING_DEFAULTS,
    check_setting,
    normalised_setting,
)

if TYPE_CHECKING:
    from ..model.terms import JointModel
    from ..model.truth import TrueJoint
    from .fourier import FourierMotion


@dataclass(frozen=True)
class Settings:
    """One synthetic identification experiment: motion, noise bound (N m), samples, seed and fitted model."""

    motion: str | FourierMotion = SETTING_DEFAULTS["motion"]
    """A training motion's name, or a designed FourierMotion (from `jointid design` or a motion file)."""
    noise: float = SETTING_DEFAULTS["noise"]
    samples: int = SETTING_DEFAULTS["samples"]
    seed: int = SETTING_DEFAULTS["seed"]
    model: str = SETTING_DEFAULTS["model"]
    """The fitted model's name ('plain', 'bias', 'coulomb+bias', ...; see jointid.model.terms)."""
    true_coulomb: float = SETTING_DEFAULTS["true_coulomb"]
    """Coulomb friction FC (N m) of the synthetic joint: it adds FC*sign(qd)."""
    true_bias: float = SETTING_DEFAULTS["true_bias"]
    """Torque sensor bias TAU0 (N m): every reading is TAU0 too much."""
    true_angle_offset: float = SETTING_DEFAULTS["true_angle_offset"]
    """Encoder offset Q0 (rad): the logged angle is q_true - Q0."""
    constrained: bool = SETTING_DEFAULTS["constrained"]
    """Fit subject to the model's sign rules (never the default: the lesson shows the unconstrained failure)."""

    def __post_init__(self):
        for field in FIELDS:
            if field == "motion" and not isinstance(self.motion, str) and self._is_designed(self.motion):
                continue
            check_setting(field, getattr(self, field))
            # Stored as plain Python numbers: a numpy scalar would leak into JSON and into equality.
            object.__setattr__(self, field, normalised_setting(field, getattr(self, field)))

    @staticmethod
    def _is_designed(motion) -> bool:
        """True for a designed (Fourier-series) motion; its module (numpy) loads only for such a value."""
        from .fourier import FourierMotion

        return isinstance(motion, FourierMotion)

    @property
    def training_motion(self):
        """The motion object (a Motion or a FourierMotion) the experiment trains on."""
        from .motions import TRAINING_MOTIONS  # numpy: only when data are generated

        return TRAINING_MOTIONS[self.motion] if isinstance(self.motion, str) else self.motion

    @property
    def motion_name(self) -> str:
        """The training motion's name: 'rich', 'slow', 'holds' or 'design'."""
        return self.training_motion.name

    @property
    def joint_model(self) -> JointModel:
        """The JointModel that `model` names."""
        from ..model.terms import model_named  # numpy: only when a fit needs the model

        return model_named(self.model)

    @property
    def true_joint(self) -> TrueJoint:
        """The synthetic joint with these settings' missing physics."""
        from ..model.truth import TrueJoint  # numpy: only when data are generated

        return TrueJoint(coulomb=self.true_coulomb, bias=self.true_bias, angle_offset=self.true_angle_offset)


DEFAULT_SETTINGS = Settings()
"""Rich motion, no noise, 24 samples, seed 7: the lesson's starting point."""
