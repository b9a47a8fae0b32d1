"""`jointid` with no subcommand: the terminal explorer."""

from __future__ import annotations

from .arguments import UserError, settings_from


def run(args) -> int:
    """Open the explorer at the settings given by the flags; 0 on a normal exit."""
    settings = settings_from(args)
    # The explorer's controls cover narrower ranges than the core; say so rather than clamp.
    from tui.app import NOISE_RANGE, SAMPLES_RANGE  # lazy: `import jointid` never loads textual

    for steps in (NOISE_RANGE, SAMPLES_RANGE):
        value = getattr(settings, steps.field)
        if not steps.low <= value <= steps.high:
            raise UserError(
                f"the explorer's --{steps.field} is {steps.describe()}; got {steps.format(value)}. "
                f"Use `jointid fit --{steps.field} {steps.format(value)}` for larger values."
            )
    from tui.app import JointIdApp

    JointIdApp(settings).run()
    return 0
