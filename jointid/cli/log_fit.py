"""`jointid fit --csv`: the options and the run for fitting CSV joint logs.

Synthetic settings (--motion, --noise, --samples, --seed, --true-*) describe generated
data, so they cannot apply to a log: giving them with --csv is an error (one
line, exit 2) rather than something silently ignored. To tell a flag the user
typed from its default, `fit` parses them with default None and fills the
defaults in afterwards (`with_default_settings`).
"""

from __future__ import annotations

import argparse

from ..choices import DEFAULT_ORDER, SETTING_DEFAULTS
from .arguments import UserError, finite_float, whole_number
from .output import print_json

TYPE_CHECKING = False  # typing itself would cost 3 ms of every start
if TYPE_CHECKING:
    from ..csvlog import JointLog
    from ..logfit import LoadedLogs

SETTING_FLAGS = ("motion", "noise", "samples", "seed", "true_coulomb", "true_bias", "true_angle_offset")
"""Synthetic-experiment options that a log fit rejects."""

LOG_ONLY_FLAGS = ("heldout", "degrees", "window", "order", "cutoff", "decimate")
"""Options that mean something only with --csv."""

SYNTHETIC_ONLY_FLAGS = ("simulate", "horizon")
"""Options that need the synthetic joint's true torque, which a log does not have."""


def add_log_arguments(parser: argparse.ArgumentParser) -> None:
    """Add --csv, --heldout, --degrees, --window and --order, and make setting flags detectable."""
    group = parser.add_argument_group(
        "joint logs (CSV: t, q, qd, qdd, tau by header name)",
        "Fit a logged joint instead of a synthetic experiment; --motion, --noise, --samples, --seed and "
        "--true-* describe synthetic data and are refused with --csv.",
    )
    group.add_argument("--csv", metavar="TRAIN.csv", help="fit this log instead of a synthetic experiment")
    group.add_argument("--heldout", metavar="TEST.csv",
                       help="predict this log's measured torques with the fit (needs --csv)")
    group.add_argument("--degrees", action="store_true", help="the logs give q, qd, qdd in degrees")
    group.add_argument("--window", type=whole_number(3), default=None, metavar="W",
                       help="Savitzky-Golay window (odd number of samples) when qd or qdd is missing; "
                       "default: chosen from the motion's bandwidth and q's noise (the note says which)")
    group.add_argument("--order", type=whole_number(2), default=None, metavar="P",
                       help=f"Savitzky-Golay polynomial order; default {DEFAULT_ORDER}")
    group.add_argument("--cutoff", type=cutoff_number, default=None, metavar="HZ",
                       help="low-pass the torque and every regressor column alike at HZ (zero phase) before the "
                       "fit; 0 turns it off; default: 12 times the motion's bandwidth")
    group.add_argument("--decimate", type=whole_number(1), default=None, metavar="N",
                       help="keep every Nth sample after the low-pass; default: down to twice the cutoff")
    parser.set_defaults(**dict.fromkeys(SETTING_FLAGS))


def with_default_settings(args: argparse.Namespace) -> argparse.Namespace:
    """Reject log-only flags without --csv, and fill unset synthetic settings with their defaults."""
    stray = [f"--{name}" for name in LOG_ONLY_FLAGS if getattr(args, name) not in (None, False)]
    if stray:
        raise UserError(f"{', '.join(stray)}: only for fitting a log; add --csv TRAIN.csv")
    for name in SETTING_FLAGS:
        if getattr(args, name) is None:
            setattr(args, name, SETTING_DEFAULTS[name])
    return args


def cutoff_number(text: str) -> float:
    """An argparse type for --cutoff: a finite number of hertz, 0 (off) or more."""
    value = finite_float(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be a number of hertz, 0 (off) or more; got {text!r}")
    return value


def filter_options(args: argparse.Namespace):
    """The parallel low-pass asked for by --cutoff and --decimate (None: automatic): a FilterRequest."""
    from ..parallel_filter import FilterRequest

    return FilterRequest(getattr(args, "cutoff", None), getattr(args, "decimate", None))


def derivative_options(args: argparse.Namespace) -> tuple[int | None, int]:
    """The Savitzky-Golay window (None: automatic) and order from --window and --order; UserError if they do
    not fit together."""
    from ..derivatives import FilterSettingError, check_filter  # numpy: only once a command runs

    window = args.window
    order = DEFAULT_ORDER if args.order is None else args.order
    try:
        check_filter(window, order)
    except FilterSettingError as error:
        raise UserError(f"argument --{error.field}: {error.problem}") from None
    return window, order


def load_logs(args: argparse.Namespace) -> tuple[JointLog, JointLog | None]:
    """The --csv and --heldout logs, after checking the options; UserError (one line) on any problem."""
    given = [f"--{name.replace('_', '-')}" for name in SETTING_FLAGS if getattr(args, name) is not None]
    if getattr(args, "motion_file", None) is not None:
        given.append("--motion-file")
    if given:
        raise UserError(f"synthetic settings ({', '.join(given)}) cannot apply to a --csv log; drop them")
    simulated = [f"--{name}" for name in SYNTHETIC_ONLY_FLAGS if getattr(args, name, None) not in (None, False)]
    if simulated:
        raise UserError(f"{', '.join(simulated)}: needs the synthetic joint's true torque, which a log does not "
                        "have; drop it")
    window, order = derivative_options(args)
    from ..csvlog import LogError, load_log

    try:
        training = load_log(args.csv, degrees=args.degrees, window=window, order=order)
        heldout = None if args.heldout is None else load_log(
            args.heldout, degrees=args.degrees, window=window, order=order
        )
    except LogError as error:
        raise UserError(str(error)) from None
    return training, heldout


def fit_loaded_logs(args: argparse.Namespace) -> LoadedLogs:
    """The --csv (and --heldout) logs loaded and fitted with --model (and --constrained); UserError (one line)
    on any problem."""
    training, heldout = load_logs(args)
    # Imported after the load: code loaded before it would add to the load's peak resident set.
    from ..csvlog import LogError
    from ..logfit import fit_logs
    from ..model import model_named

    try:
        return fit_logs(training, heldout, model=model_named(args.model),
                        constrained=getattr(args, "constrained", False), filtering=filter_options(args))
    except LogError as error:  # numbers beyond double precision
        raise UserError(str(error)) from None


def run_log_fit(args: argparse.Namespace) -> int:
    """Load the training (and held-out) log, fit, and print text or JSON; exit status 0."""
    logs = fit_loaded_logs(args)
    from ..present.readouts import readouts_text, uncertainty_text

    if args.json:
        print_json(logs.document())
        return 0
    print("\n".join(logs.source_lines()))
    print(readouts_text(logs.result))
    print()
    print(uncertainty_text(logs.result))
    if logs.sensitivity is not None:
        from ..present.sensitivity import sensitivity_text

        print(sensitivity_text(logs.sensitivity))
    if logs.notes():
        print()
        print("\n".join(f"Note: {note}" for note in logs.notes()))
    return 0
