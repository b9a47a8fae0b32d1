"""The four settings of a synthetic experiment, their ranges and their parsing."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .motions import TRAINING_MOTIONS

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
    """One synthetic identification experiment: motion, noise bound (N m), samples and seed."""

    motion: str = "rich"
    noise: float = 0.0
    samples: int = 24
    seed: int = 7

    def __post_init__(self):
        check_setting("motion", self.motion)
        check_setting("noise", self.noise)
        check_setting("samples", self.samples)
        check_setting("seed", self.seed)



def describe_range(field: str) -> str:
    """The allowed values of a setting, as a phrase for error messages and help."""
    if field == "motion":
        return "one of " + ", ".join(TRAINING_MOTIONS)
    if field == "noise":
        low, high = NOISE_LIMITS
        return f"a number from {low:g} to {high:g} (N m)"
    low, high = SAMPLES_LIMITS if field == "samples" else SEED_LIMITS
    return f"a whole number from {low} to {high}"


def check_setting(field: str, value) -> None:
    """Raise SettingsError unless value is allowed for the named setting."""
    if field == "motion":
        ok = value in TRAINING_MOTIONS
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
    """Convert typed text to a valid value of the named setting, or raise SettingsError."""
    text = text.strip()
    try:
        if field == "motion":
            value = text.lower()
        elif field == "noise":
            value = float(text)
        else:
            value = int(text)
        check_setting(field, value)
    except ValueError:  # SettingsError too: quote what the user typed, not the parsed value
        raise SettingsError(field, f"{field} must be {describe_range(field)}; got {text!r}") from None
    return value


DEFAULT_SETTINGS = Settings()
"""Rich motion, no noise, 24 samples, seed 7: the lesson's starting point."""
