"""What a user may choose, without numpy: motion and model names, defaults and allowed ranges.

The command line builds its parser and help from these before numpy loads
(`jointid --help` must not import it), so they live here once and the
numeric modules (motions, model, truth, derivatives, simulation, sweep)
import them from here.
"""

from __future__ import annotations

DURATION = 8.0
"""Every motion is sampled over 0 <= t <= DURATION seconds."""
VALIDATION_SAMPLES = 16
"""Number of held-out validation states on the `test` motion."""
TRAINING_MOTION_NAMES = ("rich", "slow", "holds")
"""The training motions the lab offers, in display order (`jointid.motions.TRAINING_MOTIONS` defines them)."""
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
model and none of the missing physics (`jointid.settings.Settings` takes its defaults from here)."""

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
"""Default Savitzky-Golay window: None, chosen from the log by `jointid.derivatives.choose_window` (its span in
time from the motion's bandwidth)."""
DEFAULT_ORDER = 6
"""Default polynomial order: unbiased for quartics, so curvature inside the window costs little."""
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
seeds took 3 minutes). The command line refuses more unless forced; see `jointid.sweep.sweep_work`."""


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
