"""`jointid` with no subcommand: the terminal explorer, on synthetic settings or on a --csv log."""

from __future__ import annotations

from .arguments import UserError, settings_from
from .log_fit import derivative_options, load_logs, with_default_settings


def run(args) -> int:
    """Open the explorer at the settings given by the flags, or on the --csv log; 0 on a normal exit."""
    # A bad log is one line on stderr and status 2 before the app starts, as for `jointid fit --csv`.
    logs = load_logs(args) if args.csv is not None else None
    derivatives = derivative_options(args)  # also for logs opened later with Ctrl+O
    settings = settings_from(with_default_settings(args) if logs is None else _defaults(args))
    # The explorer's controls cover narrower ranges than the core; say so rather than clamp.
    # Imported here, not at the top: `import jointid` must never load textual.
    from tui.app import NOISE_RANGE, SAMPLES_RANGE, JointIdApp
    from tui.log_source import fit_logs

    for steps in (NOISE_RANGE, SAMPLES_RANGE):
        value = getattr(settings, steps.field)
        if not steps.low <= value <= steps.high:
            raise UserError(
                f"the explorer's --{steps.field} is {steps.describe()}; got {steps.format(value)}. "
                f"Use `jointid fit --{steps.field} {steps.format(value)}` for larger values."
            )
    JointIdApp(settings, None if logs is None else fit_logs(*logs), derivatives=derivatives).run()
    return 0


def _defaults(args):
    """The synthetic defaults behind a log (load_logs has refused any setting flag already)."""
    for name in ("window", "order", "heldout", "degrees"):
        setattr(args, name, None)
    return with_default_settings(args)
