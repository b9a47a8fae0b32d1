"""The explorer's setting controls: their ranges, step sizes and labels, and the check of a start-up value."""

from __future__ import annotations

from jointid.options import ANGLE_OFFSET_LIMITS, BIAS_LIMITS, COULOMB_LIMITS, SEED_LIMITS, SettingsError
from jointid.synthetic.settings import Settings

from .widgets.stepper import StepRange

NOISE_RANGE = StepRange("noise", 0.0, 1.0, 0.01, 0.1, decimals=2, unit="N m")
"""The explorer's noise control: 0.00 to 1.00 N m (the core allows more; `jointid fit` takes it)."""
SAMPLES_RANGE = StepRange("samples", 2, 240, 1, 10)
"""The explorer's sample-count control: 2 to 240."""
SEED_RANGE = StepRange("seed", SEED_LIMITS[0], SEED_LIMITS[1], 1, 100)
"""The explorer's seed control: the core's whole seed range."""
STEP_RANGES = (NOISE_RANGE, SAMPLES_RANGE, SEED_RANGE)
"""Every numeric control, in display order."""

FIELD_LABELS = {
    "noise": "Torque noise bound (N m)",
    "samples": "Training samples",
    "seed": "Seed",
}
"""Label shown beside each numeric control."""


def check_explorer_settings(settings: Settings) -> None:
    """Raise SettingsError when a setting is outside the explorer's (narrower) range, saying what takes it."""
    for steps in (NOISE_RANGE, SAMPLES_RANGE):
        value = getattr(settings, steps.field)
        if not steps.low <= value <= steps.high:
            raise SettingsError(
                steps.field,
                f"the explorer's --{steps.field} is {steps.describe()}; got {steps.format(value)}. "
                f"Use `jointid fit --{steps.field} {steps.format(value)}` for larger values.",
            )

PHYSICS_RANGES = (
    # Labelled as the dialog and `jointid fit --true-coulomb FC` name them: a message never shows true_coulomb.
    StepRange("true_coulomb", *COULOMB_LIMITS, 0.05, 0.5, decimals=2, unit="N m", label="Coulomb friction FC"),
    StepRange("true_bias", *BIAS_LIMITS, 0.05, 0.5, decimals=2, unit="N m", label="sensor bias TAU0"),
    StepRange("true_angle_offset", *ANGLE_OFFSET_LIMITS, 0.01, 0.05, decimals=2, unit="rad",
              label="encoder offset Q0"),
)
"""The physics dialog's fields: the synthetic joint's Coulomb friction, sensor bias and encoder offset."""

PHYSICS_LABELS = {
    "true_coulomb": "Coulomb friction FC (N m)",
    "true_bias": "Sensor bias TAU0 (N m)",
    "true_angle_offset": "Encoder offset Q0 (rad)",
}
"""Label beside each physics field."""
