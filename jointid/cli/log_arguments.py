"""`jointid fit --csv` / `--bag` / `--wpilog`: the options and the run for fitting joint logs (CSV files, ROS bags
or WPILib data logs; a SysId routine log is fitted as its test runs).

Synthetic settings (--motion, --noise, --samples, --seed, --true-*) describe generated
data, so they cannot apply to a log: giving them with --csv is an error (one
line, exit 2) rather than something silently ignored. To tell a flag the user
typed from its default, `fit` parses them with default None and fills the
defaults in afterwards (`with_default_settings`).
"""

from __future__ import annotations

import argparse
TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (2.5 ms of every --help)

from ..options import DEFAULT_ORDER, SETTING_DEFAULTS, default_log_model
from .arguments import UserError, finite_float, whole_number
from .effort_arguments import (
    EFFORT_FLAGS,
    add_effort_arguments,
    check_gains_request,
    effort_extras,
    effort_reading,
    motor_drive,
)
from .exit_status import ExitStatus
from .output import print_json

if TYPE_CHECKING:
    from ..logs.pipeline import JointLog
    from ..studies.log_fit import LoadedLogs

SETTING_FLAGS = ("motion", "noise", "samples", "seed", "true_coulomb", "true_bias", "true_angle_offset")
"""Synthetic-experiment options that a log fit rejects."""

LOG_ONLY_FLAGS = ("heldout", "degrees", "window", "order", "cutoff", "decimate", "exclude", "no_robust", "joint",
                  "topic", "train_window", "heldout_window", "effort_scale", "columns", "zero", "clockwise", "entry",
                  "units", "sysid_motor", "sysid_runs", *EFFORT_FLAGS)
"""Options that mean something only with --csv or --bag."""

BAG_ONLY_FLAGS = ("joint", "topic")
"""Options that mean something only with --bag."""

WPILOG_ONLY_FLAGS = ("entry", "units", "sysid_motor", "sysid_runs")
"""Options that mean something only with --wpilog."""

SYNTHETIC_ONLY_FLAGS = ("simulate", "horizon")
"""Options that need the synthetic joint's true torque, which a log does not have."""


def add_log_arguments(parser: argparse.ArgumentParser) -> None:
    """Add --csv, --bag and the options of a log fit, and make setting flags detectable."""
    group = parser.add_argument_group(
        "joint logs (CSV: t, q, qd, qdd, tau by header name or --columns; one joint of a ROS bag's "
        "sensor_msgs/JointState; or a WPILib data log's entries)",
        "Fit a logged joint instead of a synthetic experiment; --motion, --noise, --samples, --seed and "
        "--true-* describe synthetic data and are refused with a log.",
    )
    source = group.add_mutually_exclusive_group()
    source.add_argument("--csv", metavar="TRAIN.csv", action=_LogRuns,
                        help="fit this log instead of a synthetic experiment; repeat it for several runs of one "
                        "joint, fitted alone and together")
    source.add_argument("--bag", metavar="BAG",
                        help="fit one joint of this ROS bag (ROS 1 .bag, ROS 2 folder, .mcap or .db3; "
                        "needs pip install 'jointid[ros]')")
    source.add_argument("--wpilog", metavar="LOG.wpilog",
                        help="fit a WPILib data log: a SysId routine log's tests as runs of one joint, or the "
                        "entries named by --entry (needs pip install 'jointid[wpilib]')")
    group.add_argument("--entry", type=_entry_map, metavar="MAP",
                       help="which data-log entry gives which quantity, e.g. q=/Arm/Position,qd=/Arm/Velocity,"
                       "tau=/Arm/Voltage (quantities: q, qd, qdd, tau, and state for a SysId test-state entry); "
                       "default: a SysId routine's entries (`jointid log-info` lists them)")
    group.add_argument("--units", choices=UNIT_CHOICES, default=None,
                       help="the data log's unit for q, qd and qdd, over any unit its metadata names (meters: a "
                       "length, kept as one; the others are angles); default: the metadata's (WPILib's "
                       "SysIdRoutineLog writes it)")
    group.add_argument("--sysid-motor", metavar="NAME", default=None,
                       help="fit one motor of a SysId routine that logs several (voltage-NAME-ROUTINE...), or name "
                       "the routine to fit; default: every motor of the log's routine, pooled as one mechanism")
    group.add_argument("--sysid-runs", choices=("all", "first"), default=None,
                       help="a SysId test run more than once: fit every run (all, the default), or each test's "
                       "first run as SysId's analysis does (first)")
    group.add_argument("--joint", metavar="NAME", help="the bag's joint to fit (its name in JointState)")
    group.add_argument("--topic", metavar="TOPIC",
                       help="the bag's JointState topic; default: its only one, or /joint_states")
    group.add_argument("--heldout", metavar="TEST",
                       help="predict this log's measured torques with the fit (a CSV log, or a bag read like --bag)")
    group.add_argument("--train-window", type=_time_window, metavar="START:END",
                       help="fit only the samples from START to END seconds after the log's start (a data log's: "
                       "seconds of its own time stamps, as log-info lists them)")
    group.add_argument("--heldout-window", type=_time_window, metavar="START:END",
                       help="predict the samples from START to END seconds after the start of the held-out log "
                       "(without --heldout: of the training log itself)")
    group.add_argument("--effort-scale", type=_effort_scale, metavar="K",
                       help="the effort's unit (N m, or V with --effort voltage) per unit of the logged effort or "
                       "tau, e.g. 12 for a duty cycle; default 1 (a current's is --gear x --kt x --efficiency)")
    group.add_argument("--columns", type=_column_map, metavar="MAP",
                       help="which CSV column gives which quantity, e.g. t=time,q=posn,tau=effort (quantities: t, q, "
                       "qd, qdd, tau); default: by name, t/time/timestamp, q/position/pos/angle, qd/velocity/vel, "
                       "qdd/acceleration/accel, tau/torque/effort (a suffixed name such as position_rad only "
                       "through this map)")
    add_reading_arguments(group)
    group.add_argument("--exclude", type=_time_window, action="append", default=None, metavar="START:END",
                       help="leave out the samples from START to END seconds after the log's start (a data log's: "
                       "seconds of its own time stamps) (repeatable), "
                       "e.g. where you know an outside torque acted")
    group.add_argument("--no-robust", action="store_true",
                       help="keep every sample: do not look for outside torques (pushes, collisions) to leave out")
    add_effort_arguments(group)
    parser.set_defaults(**dict.fromkeys(SETTING_FLAGS))


def add_reading_arguments(group) -> None:
    """The flags that say how a joint's samples are read and filtered before the fit (--zero, --clockwise,
    --degrees, --window, --order, --cutoff, --decimate): a log's, and `watch`'s for samples as they arrive."""
    group.add_argument("--zero", choices=ZERO_CHOICES, default=None,
                       help="where the log's angle 0 points: right (jointid's own q = 0, the default), up, left, or "
                       "down (a pendulum hanging); q = angle + pi/2, + pi or - pi/2")
    group.add_argument("--clockwise", action="store_true",
                       help="the log's angle grows clockwise: q, qd, qdd and the torque change sign (the log's "
                       "positive torque turns toward increasing logged angle)")
    group.add_argument("--degrees", action="store_true", help="the logs give q, qd, qdd in degrees")
    group.add_argument("--window", type=whole_number(3), default=None, metavar="W",
                       help="Savitzky-Golay window (odd number of samples) smoothing q before qd and qdd are "
                       "estimated from it; default: its -3 dB point at 3 times the cutoff (the note says which)")
    group.add_argument("--order", type=whole_number(2), default=None, metavar="P",
                       help=f"Savitzky-Golay polynomial order; default {DEFAULT_ORDER}")
    group.add_argument("--cutoff", type=cutoff_number, default=None, metavar="HZ",
                       help="low-pass the torque and every regressor column alike at HZ (zero phase) before the "
                       "fit; 0 turns it off; default: 3 times the motion's bandwidth (the note says why)")
    group.add_argument("--decimate", type=whole_number(1), default=None, metavar="N",
                       help="keep every Nth sample after the low-pass; default: about 20 per cutoff hertz")


class _LogRuns(argparse.Action):
    """--csv, repeatable: `csv` is the first log (the training log of a single fit), `runs` every one given."""

    def __call__(self, parser, namespace, values, option_string=None):
        runs = getattr(namespace, "runs", None)
        if runs is None:
            runs = namespace.runs = []
        runs.append(values)  # in place: a copy per --csv would make many runs quadratic
        namespace.csv = runs[0]


def _time_window(text: str):
    """argparse type of --train-window and --heldout-window."""
    from ..logs.timewindow import parse_time_window

    try:
        return parse_time_window(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


ZERO_CHOICES = ("right", "up", "left", "down")
UNIT_CHOICES = ("rotations", "radians", "degrees", "meters")
"""--units's choices, as jointid.logs.wpilog.UNITS names them (not imported: help starts without numpy)."""
"""--zero's choices, as jointid.logs.conventions.ZEROS names them (not imported: help starts without it)."""


def _column_map(text: str):
    """argparse type of --columns: a conventions.ColumnMap."""
    from ..logs.conventions import ColumnMap, ColumnMapError

    try:
        return ColumnMap.parse(text)
    except ColumnMapError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def _entry_map(text: str):
    """argparse type of --entry: a conventions.EntryMap."""
    from ..logs.conventions import ColumnMapError, EntryMap

    try:
        return EntryMap.parse(text)
    except ColumnMapError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def _effort_scale(text: str) -> float:
    """argparse type of --effort-scale: a finite number other than 0."""
    value = finite_float(text)
    if value == 0:
        raise argparse.ArgumentTypeError(f"must be a finite number other than 0; got {text!r}")
    return value


def has_log(args: argparse.Namespace) -> bool:
    """True when the command line names a log (--csv, --bag or --wpilog)."""
    return any(getattr(args, name, None) is not None for name in ("csv", "bag", "wpilog"))


def with_default_settings(args: argparse.Namespace) -> argparse.Namespace:
    """Reject log-only flags without --csv, and fill unset synthetic settings with their defaults."""
    stray = [_flag(name) for name in LOG_ONLY_FLAGS if getattr(args, name) not in (None, False)]
    if stray:
        raise UserError(f"{', '.join(stray)}: only for fitting a log; add --csv TRAIN.csv, --bag BAG --joint NAME "
                        "or --wpilog LOG.wpilog")
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
    from ..estimation.low_pass import FilterRequest

    return FilterRequest(getattr(args, "cutoff", None), getattr(args, "decimate", None))


def exclusion_options(args: argparse.Namespace):
    """What --exclude and --no-robust ask a log's fit to leave out: an ExclusionRequest."""
    from ..estimation.exclusion import ExclusionRequest

    windows = getattr(args, "exclude", None) or ()
    return ExclusionRequest(robust=not getattr(args, "no_robust", False),
                            by_hand=tuple((window.start, window.end) for window in windows))


def convention_options(args: argparse.Namespace):
    """The column map, angle convention, effort and motor of --columns, --zero, --clockwise, --effort (and its
    gearing) and --motor: a conventions.LogConventions, or None when none is given (the explorer then starts
    without importing them); UserError on a bad mix of the effort and motor options."""
    efforts = any(getattr(args, name, None) is not None for name in EFFORT_FLAGS)
    if getattr(args, "columns", None) is None and getattr(args, "zero", None) is None \
            and not getattr(args, "clockwise", False) and not efforts:
        return None
    from ..logs.conventions import AngleConvention, LogConventions

    effort = effort_reading(args) if efforts else None
    return LogConventions(getattr(args, "columns", None),
                          AngleConvention(getattr(args, "zero", None) or "right", bool(getattr(args, "clockwise", False))),
                          None if effort is None or effort.kind == "torque" else effort,
                          motor_drive(args) if efforts else None)


def _conventions_or_defaults(args: argparse.Namespace):
    """convention_options, or jointid's own conventions when no flag asks for others."""
    from ..logs.conventions import LogConventions

    return convention_options(args) or LogConventions()


def derivative_options(args: argparse.Namespace) -> tuple[int | None, int]:
    """The Savitzky-Golay window (None: automatic) and order from --window and --order; UserError if they do
    not fit together."""
    from ..logs.derivatives import FilterSettingError, check_filter  # numpy: only once a command runs

    window = args.window
    order = DEFAULT_ORDER if args.order is None else args.order
    try:
        check_filter(window, order)
    except FilterSettingError as error:
        raise UserError(f"argument --{error.field}: {error.problem}") from None
    return window, order


def _flag(name: str) -> str:
    """'train_window' -> '--train-window'."""
    return "--" + name.replace("_", "-")


def log_requests(args: argparse.Namespace):
    """The training and held-out logsource.LoadRequest (or None) of --csv/--bag and the log options; UserError
    on a bad mix."""
    given = [_flag(name) for name in SETTING_FLAGS if getattr(args, name) is not None]
    if getattr(args, "motion_file", None) is not None:
        given.append("--motion-file")
    if given:
        raise UserError(f"synthetic settings ({', '.join(given)}) cannot apply to a log; drop them")
    simulated = [f"--{name}" for name in SYNTHETIC_ONLY_FLAGS if getattr(args, name, None) not in (None, False)]
    if simulated:
        raise UserError(f"{', '.join(simulated)}: needs the synthetic joint's true torque, which a log does not "
                        "have; drop it")
    wpilog = getattr(args, "wpilog", None)
    if wpilog is None:
        stray = [_flag(name) for name in WPILOG_ONLY_FLAGS if getattr(args, name, None) is not None]
        if stray:
            raise UserError(f"{', '.join(stray)}: only for a WPILib data log; use --wpilog LOG.wpilog")
    elif args.columns is not None:
        raise UserError("--columns: only for a CSV log; name a data log's entries with --entry")
    if args.bag is None:
        stray = [_flag(name) for name in BAG_ONLY_FLAGS if getattr(args, name) is not None]
        if stray:
            raise UserError(f"{', '.join(stray)}: only for a ROS bag; use --bag BAG")
    elif args.joint is None:
        raise UserError("--bag needs --joint NAME (`jointid bag-info BAG` lists the joints)")
    elif args.columns is not None:
        raise UserError("--columns: only for a CSV log; a bag's JointState gives position, velocity and effort "
                        "by name")
    from ..logs.request import HELDOUT, TRAINING, LoadRequest

    window, order = derivative_options(args)
    if wpilog is None:  # a SysId data log is in volts whatever --effort says: its fit's model decides (effort_extras)
        check_gains_request(args)
    common = dict(degrees=args.degrees, window=window, order=order, joint=args.joint, topic=args.topic,
                  effort_scale=1.0 if args.effort_scale is None else args.effort_scale, filtering=filter_options(args),
                  **_conventions_or_defaults(args).request_fields())
    if wpilog is not None:
        common.update(wpilog=True, entries=args.entry, units=args.units, sysid_motor=args.sysid_motor,
                      sysid_runs=args.sysid_runs or "all")
    path = args.bag if args.bag is not None else (wpilog if wpilog is not None else args.csv)
    training = LoadRequest(path, TRAINING, time_window=args.train_window, **common)
    if args.heldout is None and args.heldout_window is None:
        return training, None
    heldout_path = path if args.heldout is None else args.heldout
    if args.heldout is not None and args.bag is not None and not _looks_like_bag(args.heldout):
        raise UserError(f"--heldout {args.heldout}: with --bag the held-out log is a bag too (a ROS 2 folder, "
                        ".bag, .mcap or .db3)")
    if args.heldout is not None and args.bag is None and wpilog is None and _looks_like_bag(args.heldout):
        raise UserError(f"--heldout {args.heldout}: a bag; fit a bag with --bag BAG --joint NAME")
    return training, LoadRequest(heldout_path, HELDOUT, time_window=args.heldout_window, **common)


def _looks_like_bag(path: str) -> bool:
    """bag.looks_like_bag, imported only when a held-out log is named."""
    from ..logs.bag import looks_like_bag

    return looks_like_bag(path)


def load_logs(args: argparse.Namespace) -> tuple[JointLog, JointLog | None]:
    """The training and held-out logs, after checking the options; UserError (one line) on any problem."""
    from ..logs.request import load_joint_log
    from ..logs.table import LogError

    training_request, heldout_request = log_requests(args)
    try:
        training = load_joint_log(training_request)
        heldout = None if heldout_request is None else load_joint_log(heldout_request)
    except LogError as error:
        raise UserError(str(error)) from None
    return training, heldout


def fit_loaded_logs(args: argparse.Namespace) -> LoadedLogs:
    """The --csv/--bag (and held-out) logs loaded and fitted with --model (and --constrained); UserError (one line)
    on any problem."""
    training, heldout = load_logs(args)
    # Imported after the load: code loaded before it would add to the load's peak resident set.
    from ..logs.table import LogError
    from ..model.terms import model_named
    from ..studies.log_fit import fit_logs

    mechanism = getattr(args, "mechanism", None)
    if mechanism is not None and args.model is None:
        from ..studies.mechanism import mechanism_model

        model = mechanism_model(mechanism)
    else:
        model = model_named(args.model or log_model(args))
    try:
        with fit_progress(args, training.data.count):
            return fit_logs(training, heldout, model=model,
                            constrained=getattr(args, "constrained", False), filtering=filter_options(args),
                            exclusion=exclusion_options(args))
    except LogError as error:  # numbers beyond double precision
        raise UserError(str(error)) from None


def fit_progress(args: argparse.Namespace, count: int):
    """The seconds of a fit at an explicit --decimate on a terminal (such a fit may take minutes), with the memory
    it takes; nothing otherwise."""
    import contextlib

    if getattr(args, "decimate", None) is None:
        return contextlib.nullcontext()
    from ..memory import in_words
    from ..studies.log_fit import fit_memory
    from .progress import elapsed_on_terminal

    kept = -(-count // args.decimate)
    return elapsed_on_terminal(f"jointid: fitting {kept:,} samples (about {in_words(fit_memory(count, args.decimate))}"
                               " of memory)")


def log_model(args: argparse.Namespace) -> str:
    """The model a log is fitted with when --model is not given: SysId's arm for a voltage log, else LOG_MODEL."""
    return default_log_model(getattr(args, "effort", None))


def fit_any_logs(args: argparse.Namespace):
    """The fitted log(s) the command line names: several runs (repeated --csv, or a SysId data log's tests) as a
    studies.runs.PooledRuns, else a LoadedLogs; UserError (one line) on any problem."""
    if getattr(args, "mechanism", None) is not None and args.model is not None:
        raise UserError(f"--mechanism {args.mechanism} and --model {args.model}: a mechanism is a model; give one")
    if several_runs(args):
        return fit_pooled_runs(args)
    if getattr(args, "wpilog", None) is None:
        return fit_loaded_logs(args)
    training, heldout = log_requests(args)
    from ..logs.request import load_joint_logs
    from ..logs.table import LogError

    try:
        logs = load_joint_logs(training)
    except LogError as error:
        raise UserError(str(error)) from None
    from ..model.terms import model_named

    model = None if args.model is None else model_named(args.model)
    if logs[0].effort.is_torque and len(logs) == 1:  # a torque log's entries: a joint, not a routine's mechanism
        from ..logs.request import load_joint_log
        from ..studies.log_fit import fit_logs

        from ..studies.angle_models import no_angle
        from ..studies.sysid import sysid_model

        try:
            other = None if heldout is None else load_joint_log(heldout)
            if no_angle(logs[0]) is not None:  # a length or an integrated velocity: no cos(q)
                model = sysid_model(logs, model)
            return fit_logs(logs[0], other, model=model or model_named(log_model(args)),
                            constrained=getattr(args, "constrained", False), filtering=filter_options(args),
                            exclusion=exclusion_options(args))
        except LogError as error:
            raise UserError(str(error)) from None
    if heldout is not None and len(logs) > 1:
        raise UserError(f"--heldout and --heldout-window: {training.path} is a SysId log of {len(logs)} tests, each "
                        "predicted by the others instead; drop them")
    from ..logs.request import load_joint_log
    from ..studies.mechanism import MechanismError
    from ..studies.sysid import fit_sysid

    try:
        other = None if heldout is None else load_joint_log(heldout)
        return fit_sysid(logs, model, filter_options(args), exclusion_options(args),
                         getattr(args, "constrained", False), mechanism=getattr(args, "mechanism", None),
                         heldout=other)
    except (LogError, MechanismError) as error:
        raise UserError(str(error)) from None


def run_log_fit(args: argparse.Namespace) -> int:
    """Load the training (and held-out) log(s), fit, and print text or JSON (with the motor and gains asked for);
    exit status 0."""
    logs = fit_any_logs(args)
    if hasattr(logs, "shared"):
        return print_runs(args, logs)
    paragraphs, fields = effort_extras(args, logs)
    if args.json:
        from ..present.documents import logs_document

        print_json({**logs_document(logs), **fields})
    else:
        from ..present.summary import log_fit_summary

        print("\n\n".join([log_fit_summary(logs), *paragraphs]))
    return ExitStatus.SUCCESS


def fit_pooled_runs(args: argparse.Namespace):
    """Several runs of one joint (--csv given more than once), each fitted alone, then together (a
    studies.runs.PooledRuns); UserError (one line) on any problem."""
    if args.heldout is not None or args.heldout_window is not None:
        raise UserError("--heldout and --heldout-window: with several runs each run is predicted by the others "
                        "instead; drop them")
    import dataclasses

    from ..logs.request import load_joint_log
    from ..logs.table import LogError
    from ..model.terms import model_named
    from ..studies.runs import fit_runs

    training, _ = log_requests(args)
    try:
        logs = [load_joint_log(dataclasses.replace(training, path=path)) for path in args.runs]
        return fit_runs(logs, model_named(args.model or log_model(args)), filter_options(args), exclusion_options(args),
                        getattr(args, "constrained", False))
    except LogError as error:
        raise UserError(str(error)) from None


def several_runs(args: argparse.Namespace) -> bool:
    """Whether --csv was given more than once."""
    return len(getattr(args, "runs", None) or ()) > 1


def run_several(args: argparse.Namespace) -> int:
    """Several runs of one joint: the per-run table and the pooled fit, as text or JSON; exit status 0."""
    return print_runs(args, fit_pooled_runs(args))


def print_runs(args: argparse.Namespace, pooled) -> int:
    """Print pooled runs (with the motor and gains asked for) as text or JSON; exit status 0."""
    paragraphs, fields = effort_extras(args, pooled)
    if args.json:
        from ..present.runs import runs_document

        print_json({**runs_document(pooled), **fields})
    else:
        from ..present.runs import runs_text

        print("\n\n".join([runs_text(pooled), *paragraphs]))
    return ExitStatus.SUCCESS

