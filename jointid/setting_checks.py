"""Checking and parsing one experiment setting, without numpy or dataclasses (the command line's
parser uses these before anything heavy loads; `jointid.settings` re-exports them)."""

from __future__ import annotations

import math

from .choices import (
    ANGLE_OFFSET_LIMITS,
    BIAS_LIMITS,
    COULOMB_LIMITS,
    NOISE_LIMITS,
    SAMPLES_LIMITS,
    SEED_LIMITS,
    SETTING_DEFAULTS,
    TRAINING_MOTION_NAMES,
    ModelError,
    describe_models,
    model_extras,
)
from .number_text import parse_float, parse_int

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


FIELDS = tuple(SETTING_DEFAULTS)
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
        if isinstance(value, str):
            ok = value in TRAINING_MOTION_NAMES
        else:  # a designed motion; its module (numpy) loads only for such a value, never for typed text
            from .fourier import FourierMotion

            ok = isinstance(value, FourierMotion)
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
