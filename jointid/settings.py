"""The settings of a synthetic experiment, their ranges and their parsing.

Motion, noise, samples and seed describe the lesson's experiment; `model`
names the fitted model; the `true_*` settings add physics the plain model
cannot see to the synthetic joint (all zero by default). No numpy here: the
command line parses settings before it loads the numeric modules.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from typing import TYPE_CHECKING

from .choices import (  # noqa: F401  (NOISE_LIMITS etc. are also this module's API)
    ANGLE_OFFSET_LIMITS,
    BIAS_LIMITS,
    COULOMB_LIMITS,
    NOISE_LIMITS,
    SAMPLES_LIMITS,
    SEED_LIMITS,
    TRAINING_MOTION_NAMES,
    ModelError,
    describe_models,
    model_extras,
)
from .number_text import parse_float, parse_int

if TYPE_CHECKING:
    from .model import JointModel
    from .truth import TrueJoint

REAL_SETTINGS = {
    "noise": (NOISE_LIMITS, "N m"),
    "true_coulomb": (COULOMB_LIMITS, "N m"),
    "true_bias": (BIAS_LIMITS, "N m"),
    "true_angle_offset": (ANGLE_OFFSET_LIMITS, "rad"),
}
"""The settings that are real numbers: their (low, high) limits and unit."""


class SettingsError(ValueError):
    """A setting outside its allowed range or not of its type; the message is one line for a user."""

    def __init__(self, field: str, message: str):
        super().__init__(message)
        self.field = field


@dataclass(frozen=True)
class Settings:
    """One synthetic identification experiment: motion, noise bound (N m), samples, seed and fitted model."""

    motion: str = "rich"
    noise: float = 0.0
    samples: int = 24
    seed: int = 7
    model: str = "plain"
    """The fitted model's name ('plain', 'bias', 'coulomb+bias', ...; see jointid.model)."""
    true_coulomb: float = 0.0
    """Coulomb friction FC (N m) of the synthetic joint: it adds FC*sign(qd)."""
    true_bias: float = 0.0
    """Torque sensor bias TAU0 (N m): every reading is TAU0 too much."""
    true_angle_offset: float = 0.0
    """Encoder offset Q0 (rad): the logged angle is q_true - Q0."""
    constrained: bool = False
    """Fit subject to the model's sign rules (never the default: the lesson shows the unconstrained failure)."""

    def __post_init__(self):
        for field in FIELDS:
            check_setting(field, getattr(self, field))

    @property
    def joint_model(self) -> JointModel:
        """The JointModel that `model` names."""
        from .model import model_named  # numpy: only when a fit needs the model

        return model_named(self.model)

    @property
    def true_joint(self) -> TrueJoint:
        """The synthetic joint with these settings' missing physics."""
        from .truth import TrueJoint  # numpy: only when data are generated

        return TrueJoint(coulomb=self.true_coulomb, bias=self.true_bias, angle_offset=self.true_angle_offset)


FIELDS = ("motion", "noise", "samples", "seed", "model", "true_coulomb", "true_bias", "true_angle_offset",
          "constrained")
"""Every setting, in display order."""


def describe_range(field: str, *, finite: bool = False) -> str:
    """The allowed values of a setting, as a phrase for error messages and help ('a finite number' if `finite`)."""
    if field == "motion":
        return "one of " + ", ".join(TRAINING_MOTION_NAMES)
    if field == "constrained":
        return "true or false"
    if field == "model":
        return describe_models()
    if field in REAL_SETTINGS:
        (low, high), unit = REAL_SETTINGS[field]
        return f"a {'finite ' if finite else ''}number from {low:g} to {high:g} ({unit})"
    low, high = SAMPLES_LIMITS if field == "samples" else SEED_LIMITS
    return f"a whole number from {low} to {high}"


def check_setting(field: str, value) -> None:
    """Raise SettingsError unless value is allowed for the named setting."""
    if field == "motion":
        ok = value in TRAINING_MOTION_NAMES
    elif field == "model":
        try:
            model_extras(value)
        except ModelError as error:
            raise SettingsError(field, str(error)) from None
        ok = True
    elif field in REAL_SETTINGS:
        (low, high), _ = REAL_SETTINGS[field]
        ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
        ok = ok and low <= value <= high
    elif field == "constrained":
        ok = isinstance(value, bool)
    elif field in ("samples", "seed"):
        low, high = SAMPLES_LIMITS if field == "samples" else SEED_LIMITS
        ok = isinstance(value, int) and not isinstance(value, bool) and low <= value <= high
    else:
        raise SettingsError(field, f"unknown setting {field!r}")
    if not ok:
        raise SettingsError(field, f"{field} must be {describe_range(field)}; got {value!r}")


def parse_setting(field: str, text: str):
    """Convert typed text (ASCII digits only) to a valid value of the named setting, or raise SettingsError."""
    text = text.strip()
    value = None
    try:
        if field in ("motion", "model"):
            value = text.lower()
        elif field in REAL_SETTINGS:
            value = parse_float(text)
        else:
            value = parse_int(text)
        check_setting(field, value)
    except ValueError as error:
        if field == "model":  # the model's own message quotes the name and lists the choices
            raise SettingsError(field, str(error)) from None
        # '-inf' and 'nan' are numbers, but not finite ones
        allowed = describe_range(field, finite=isinstance(value, float) and not math.isfinite(value))
        # SettingsError too: quote what the user typed, not the parsed value
        raise SettingsError(field, f"{field} must be {allowed}; got {text!r}") from None
    return value


DEFAULT_SETTINGS = Settings()
"""Rich motion, no noise, 24 samples, seed 7: the lesson's starting point."""
