"""What a user may choose, without numpy: names, defaults, allowed ranges, and how typed values are read.

The command line builds its parser and help from these before numpy loads
(`jointid --help` must not import it), and the explorer's controls and the
numeric modules take their names, defaults and limits from here, so each
exists once.
"""

from __future__ import annotations

import math
import numbers
import re

# --- Motions, models and the synthetic experiment's settings ---

DURATION = 8.0
"""Every motion is sampled over 0 <= t <= DURATION seconds."""
VALIDATION_SAMPLES = 16
"""Number of held-out validation states on the `test` motion."""
TRAINING_MOTION_NAMES = ("rich", "slow", "holds")
"""The training motions the lab offers, in display order (`jointid.synthetic.motions.TRAINING_MOTIONS` defines them)."""
VALIDATION_MOTION_NAME = "test"
"""The validation motion's name, never used for fitting."""
ALL_MOTION_NAMES = (*TRAINING_MOTION_NAMES, VALIDATION_MOTION_NAME)
"""Every motion's name, the validation motion last."""

TRUE_VALUES = {"I": 0.8, "h": 0.4, "B": 0.15}
"""The lesson's joint's parameters by symbol."""

EXTRA_TERM_NAMES = ("coulomb", "bias", "angle-offset")
"""Terms that can be added to `plain`, by the name used in model names, in column order."""
LADDER = ("plain", "coulomb", "bias", "angle-offset", "coulomb+bias", "coulomb+angle-offset")
"""The models `jointid compare` fits, simplest first."""

MECHANISM_MODEL_NAMES = ("simple", "elevator")
"""Models named by their mechanism: a simple motor (no gravity term) and an elevator (a constant one)."""

MECHANISMS = ("simple", "elevator", "arm")
"""What a SysId routine characterised (--mechanism): a simple motor (flywheel, roller, drive), an elevator, an arm."""

LOG_MODEL = "coulomb+bias"
"""The model a log is fitted with unless told otherwise: real joints have Coulomb friction and sensors a bias."""
VOLTAGE_LOG_MODEL = "coulomb+angle-offset"
"""A voltage log's default model: WPILib SysId's arm, V = kS sgn qd + kG cos(q + q0) + kV qd + kA qdd."""


def default_log_model(effort: str | None = None) -> str:
    """The model a log whose effort is `effort` ('torque', 'current', 'voltage'; None: torque) is fitted with unless
    told otherwise: the command line's, the library's and the explorer's Ctrl+O default alike."""
    return VOLTAGE_LOG_MODEL if effort == "voltage" else LOG_MODEL

SETTING_DEFAULTS = {
    "motion": "rich",
    "noise": 0.0,
    "samples": 24,
    "seed": 7,
    "model": "plain",
    "true_coulomb": 0.0,
    "true_bias": 0.0,
    "true_angle_offset": 0.0,
    "constrained": False,
}
"""Every experiment setting's default, in display order: rich motion, no noise, 24 samples, seed 7, the plain
model and none of the missing physics (`jointid.synthetic.settings.Settings` takes its defaults from here)."""

NOISE_LIMITS = (0.0, 100.0)
"""Allowed torque noise bound (N m)."""
SAMPLES_LIMITS = (2, 10_000_000)
"""Allowed number of training samples."""
SEED_LIMITS = (0, 2**32 - 1)
"""Allowed noise seed."""
COULOMB_LIMITS = (0.0, 10.0)
"""Allowed true Coulomb friction (N m)."""
BIAS_LIMITS = (-10.0, 10.0)
"""Allowed true torque sensor bias (N m)."""
ANGLE_OFFSET_LIMITS = (-0.5, 0.5)
"""Allowed true encoder offset (rad)."""

DEFAULT_HORIZON = 1.0
"""Seconds between restarts from the true state in the simulation check."""
HORIZON_LIMITS = (0.05, DURATION)
"""Allowed horizon (s): from a few integration steps to the whole motion."""

DEFAULT_WINDOW = None
"""Default Savitzky-Golay smoothing window: None, chosen from the low-pass's cutoff by
`jointid.logs.derivatives.smoothing_window`."""
DEFAULT_ORDER = 3
"""Default smoothing polynomial order: cubic, flat through its window's passband and short enough to follow
the motion's turns."""
MAX_WINDOW = 4001
"""Widest window (samples): 0.2 s at 20 kHz. The filter costs N*window operations (about 2 s for a
million rows at this width), and 0.2 s already smooths the lesson's motions; wider only costs time."""
MAX_ORDER = 10
"""Highest polynomial order: beyond it the polynomial follows the noise, and its fit costs window*order^2
(order 6999 over 7001 samples ran for minutes)."""

SEED_COUNT_LIMITS = (1, 1_000_000)
"""Allowed number of seeds in one sweep."""
DEFAULT_SEED_COUNT = 1000
"""Seeds in a sweep unless told otherwise."""
WORK_BUDGET = 100_000_000
"""Samples x seeds a sweep takes without being asked twice: about 10 s here (1,000,000 samples x 1,000
seeds took 3 minutes). The command line refuses more unless forced; see `jointid.studies.sweep.sweep_work`."""


class ModelError(ValueError):
    """An unknown model name; the message is one line for a user."""


def describe_models() -> str:
    """The accepted model names, as a phrase for help and error messages."""
    extras = ", ".join(EXTRA_TERM_NAMES)
    return f"plain, or plain plus any of {extras} joined with + (e.g. coulomb+bias)"


def model_extras(name: str) -> tuple[str, ...]:
    """The extra terms a model name like 'plain' or 'coulomb+angle-offset' adds, in column order; ModelError if
    the name is not a model."""
    parts = [part.strip().lower() for part in str(name).split("+")]
    extras = [part for part in parts if part != "plain"]
    unknown = [part for part in extras if part not in EXTRA_TERM_NAMES]
    if not name or unknown or len(set(extras)) != len(extras) or "" in parts:
        raise ModelError(f"unknown model {name!r}: use {describe_models()}")
    return tuple(key for key in EXTRA_TERM_NAMES if key in extras)  # one column order whatever the spelling


# --- The excitation designer's options ---
# The excitation designer's options, defaults and ranges, without numpy: the command line's --help reads them.
#
# See `jointid.studies.design` for the designer and `jointid.synthetic.fourier` for the motions it makes.

CRITERIA = {
    "d": "D-optimal (maximise log det of the information matrix in relative units)",
    "a": "A-optimal (minimise the sum of relative variances)",
    "cond": "cond (minimise the column-scaled condition number)",
}
"""The design criteria by name, with what each optimises."""
DEFAULT_CRITERION = "d"
DEFAULT_HARMONICS = 3
DEFAULT_STARTS = 8
DEFAULT_SEED = 0
"""Seed of the random starts (not of the torque noise)."""
DEFAULT_NOISE = 0.20
"""The lesson's noise bound (N m): the expected standard errors are shown at it."""
DEFAULT_PERIOD = 8.0
"""Period T (s) of a designed motion: the lesson's 8 s window holds one period."""
PERIOD_LIMITS = (0.1, 1000.0)
"""Allowed period (s)."""
HARMONIC_LIMITS = (1, 20)
"""Allowed number of harmonics K."""
STARTS_LIMITS = (1, 1000)
"""Allowed number of random starts."""
RICH_ENVELOPE = {"q_max": 0.95, "qd_max": 1.6, "qdd_max": 3.0}
"""Rich motion's envelope, the default limits: |q| <= 0.95 rad, |qd| <= 1.6 rad/s, |qdd| <= 3.0 rad/s²."""
LIMIT_RANGES = {"q_max": (3.141592653589793, "rad"), "qd_max": (100.0, "rad/s"), "qdd_max": (1000.0, "rad/s²"),
                "tau_max": (1000.0, "N m")}
"""Largest value of each limit and its unit (the lower end, 0, is excluded)."""
LIMIT_SYMBOLS = {"q_max": "|q|", "qd_max": "|qd|", "qdd_max": "|qdd|", "tau_max": "|tau|"}
"""How a printout names the quantity each limit bounds."""


# --- Numbers as a person types them ---
# Numbers as a person types them: plain ASCII decimal notation only.
#
# Python's float() and int() also accept other scripts' digits ('٣', '２') and
# digit-group underscores ('1_000'). A typed setting or flag should mean exactly
# what it shows in any terminal font, so only ASCII decimal notation is read
# here; inf and nan are still read, so that range checks can say what is wrong.

_DECIMAL = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?|[+-]?(inf|infinity|nan)", re.ASCII | re.IGNORECASE)
_WHOLE = re.compile(r"[+-]?\d+", re.ASCII)


def parse_float(text: str) -> float:
    """float(text) for ASCII decimal notation, 'inf' and 'nan' included; ValueError for anything else."""
    text = text.strip()
    if not _DECIMAL.fullmatch(text):
        raise ValueError(f"not a decimal number: {text!r}")
    return float(text)


def parse_int(text: str) -> int:
    """int(text) for ASCII decimal digits with an optional sign; ValueError for anything else."""
    text = text.strip()
    if not _WHOLE.fullmatch(text):
        raise ValueError(f"not a whole number: {text!r}")
    return int(text)  # ValueError too beyond Python's 4300-digit limit


# --- Checking and parsing one experiment setting ---
# Checking and parsing one experiment setting, without numpy or dataclasses (the command line's
# parser uses these before anything heavy loads; `jointid.synthetic.settings` re-exports them).

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


def _is_bool(value) -> bool:
    """True for Python's and numpy's booleans (numpy's is no subclass of bool)."""
    return isinstance(value, bool) or (type(value).__module__ == "numpy" and type(value).__name__ in ("bool", "bool_"))


def normalised_setting(field: str, value):
    """A checked setting's value as a plain Python number (numpy's scalars become int, float or bool)."""
    if field in REAL_SETTINGS:
        return float(value)
    if field in ("samples", "seed"):
        return int(value)
    if field == "constrained":
        return bool(value)
    return value


def check_setting(field: str, value) -> None:
    """Raise SettingsError unless value is allowed for the named setting."""
    if field == "motion":  # a name here; Settings also takes a designed motion object
        ok = isinstance(value, str) and value in TRAINING_MOTION_NAMES
    elif field == "model" and isinstance(value, str) and value.strip().lower() in MECHANISM_MODEL_NAMES:
        ok = True
    elif field == "model":
        try:
            model_extras(value)
        except ModelError as error:
            raise SettingsError(field, str(error)) from None
        ok = True
    elif field in REAL_SETTINGS:
        (low, high), _ = REAL_SETTINGS[field]
        # numbers.Real and Integral take numpy's scalars too (np.float32(0.2), np.int64(24)); bool is no number.
        ok = isinstance(value, numbers.Real) and not _is_bool(value) and math.isfinite(value)
        ok = ok and low <= value <= high
    elif field == "constrained":
        ok = _is_bool(value)
    elif field in ("samples", "seed"):
        low, high = SAMPLES_LIMITS if field == "samples" else SEED_LIMITS
        ok = isinstance(value, numbers.Integral) and not _is_bool(value) and low <= value <= high
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
