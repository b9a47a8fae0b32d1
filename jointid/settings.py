"""The settings of a synthetic experiment (motion, noise, samples, seed, fitted model), their ranges and parsing."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .model import ModelError, describe_models, model_named
from .motions import TRAINING_MOTIONS
from .number_text import parse_float, parse_int

NOISE_LIMITS = (0.0, 100.0)
"""Allowed torque noise bound (N m)."""
SAMPLES_LIMITS = (2, 10_000_000)
"""Allowed number of training samples."""
SEED_LIMITS = (0, 2**32 - 1)
"""Allowed noise seed."""


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

    def __post_init__(self):
        for field in FIELDS:
            check_setting(field, getattr(self, field))

    @property
    def joint_model(self):
        """The JointModel that `model` names."""
        return model_named(self.model)


FIELDS = ("motion", "noise", "samples", "seed", "model")
"""Every setting, in display order."""


def describe_range(field: str, *, finite: bool = False) -> str:
    """The allowed values of a setting, as a phrase for error messages and help ('a finite number' if `finite`)."""
    if field == "motion":
        return "one of " + ", ".join(TRAINING_MOTIONS)
    if field == "model":
        return describe_models()
    if field == "noise":
        low, high = NOISE_LIMITS
        return f"a {'finite ' if finite else ''}number from {low:g} to {high:g} (N m)"
    low, high = SAMPLES_LIMITS if field == "samples" else SEED_LIMITS
    return f"a whole number from {low} to {high}"


def check_setting(field: str, value) -> None:
    """Raise SettingsError unless value is allowed for the named setting."""
    if field == "motion":
        ok = value in TRAINING_MOTIONS
    elif field == "model":
        try:
            model_named(value)
        except ModelError as error:
            raise SettingsError(field, str(error)) from None
        ok = True
    elif field == "noise":
        ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
        ok = ok and NOISE_LIMITS[0] <= value <= NOISE_LIMITS[1]
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
        elif field == "noise":
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
