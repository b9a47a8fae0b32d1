"""`jointid simulate`: write a synthetic joint log in the CSV format `fit --csv` reads.

Times are t_i = duration*i/(samples-1), so samples = duration*rate + 1. Any two
of --samples, --rate and --duration fix the third; all three must agree; with
fewer, the duration defaults to 8 s and then the samples to 24. The duration
and rate are bounded (DURATION_LIMIT, RATE_LIMIT) so that every time and
every sine of the motion is a finite number with digits to spare.
"""

from __future__ import annotations

import argparse
import math

from ..options import (
    ALL_MOTION_NAMES,
    DURATION,
    SETTING_DEFAULTS,
    SettingsError,
    check_setting,
)
from .arguments import (
    UserError,
    add_motion_file_argument,
    bounded_number,
    motion_from_file,
    positive_number,
    setting_type,
    whole_number,
)
from .commands import SUBCOMMANDS
from .effort_arguments import efficiency_number
from .exit_status import ExitStatus

NAME = "simulate"

FULL_COLUMNS = ("t", "q", "qd", "qdd", "tau")
ENCODER_COLUMNS = ("t", "q", "tau")

DURATION_LIMIT = 1e6
"""Longest time span (s), about 11.6 days: beyond about 1e15 s the motion's sines have no correct digits,
and at 1e308 s they are NaN."""
ENCODER_COUNT_LIMIT = 2**32
"""Most counts per turn (a 32-bit encoder): more is no encoder, and 10**400 is no float."""
RATE_LIMIT = 1e9
"""Highest sample rate (Hz): with DURATION_LIMIT it keeps duration*rate a finite, exactly rounded count."""

JITTER_LIMIT = 0.4
"""Largest --jitter (sample steps): below half a step, samples can never swap order."""


def bounded_positive(high: float):
    """An argparse type for a finite number greater than 0 and at most `high`."""

    def parse(text: str) -> float:
        value = positive_number(text)
        if value > high:
            raise argparse.ArgumentTypeError(f"must be a number greater than 0 and at most {high:g}; got {text!r}")
        return value

    return parse


def encoder_counts(text: str) -> int:
    """An argparse type for counts per turn: a whole number from 2 to ENCODER_COUNT_LIMIT."""
    value = whole_number(2)(text)  # its message for a count below 2, as before
    if value > ENCODER_COUNT_LIMIT:
        raise argparse.ArgumentTypeError(f"must be a whole number from 2 to {ENCODER_COUNT_LIMIT:,}; got {text!r}")
    return value


def motion_name(text: str) -> str:
    """An argparse type for any motion, the validation motion `test` included."""
    name = text.strip().lower()
    if name not in ALL_MOTION_NAMES:
        raise argparse.ArgumentTypeError(f"must be one of {', '.join(ALL_MOTION_NAMES)}; got {text!r}")
    return name


def add_parser(subparsers) -> None:
    """Attach the `simulate` subcommand."""
    parser = subparsers.add_parser(
        NAME,
        help=SUBCOMMANDS[NAME].summary,
        description="Sample a motion, compute the true torque (I = 0.8, h = 0.4, B = 0.15) plus the lesson's "
        "seeded uniform noise, and write t, q, qd, qdd, tau as CSV (or, with --encoder-counts, only t, "
        "a quantised q and tau). Times are duration*i/(samples-1): any two of --samples, --rate and --duration "
        "fix the third, and three that disagree are refused. The file is written atomically and never over an "
        "existing one without --force.",
    )
    motions = parser.add_mutually_exclusive_group()
    motions.add_argument("--motion", type=motion_name, default=SETTING_DEFAULTS["motion"],
                         metavar="{" + ",".join(ALL_MOTION_NAMES) + "}",
                         help="motion to sample, the validation motion test included; "
                         f"default {SETTING_DEFAULTS['motion']}")
    add_motion_file_argument(motions)
    parser.add_argument("--noise", type=setting_type("noise"), default=SETTING_DEFAULTS["noise"], metavar="X",
                        help="bound of the uniform torque noise, 0 to 100 N m; default 0")
    parser.add_argument("--seed", type=setting_type("seed"), default=SETTING_DEFAULTS["seed"], metavar="S",
                        help=f"noise seed, 0 to 4294967295; default {SETTING_DEFAULTS['seed']}")
    parser.add_argument("--samples", type=setting_type("samples"), default=None, metavar="N",
                        help=f"number of samples, 2 to 10000000; default {SETTING_DEFAULTS['samples']} "
                        "(or duration*rate + 1 with --rate)")
    parser.add_argument("--rate", type=bounded_positive(RATE_LIMIT), default=None, metavar="HZ",
                        help=f"sample rate (Hz), at most {RATE_LIMIT:g}; samples = duration*rate + 1")
    parser.add_argument("--duration", type=bounded_positive(DURATION_LIMIT), default=None, metavar="S",
                        help=f"time span from the first to the last sample (s), at most {DURATION_LIMIT:g}; "
                        f"default {DURATION:g}")
    parser.add_argument("--jitter", type=bounded_number(0.0, JITTER_LIMIT), default=0.0, metavar="J",
                        help="take each sample (but the first and last) up to J sample steps off its tick, like a "
                        f"real logger, and write the true instants (0 to {JITTER_LIMIT:g}; seeded by --seed); default 0")
    parser.add_argument("--encoder-counts", type=encoder_counts, default=None, metavar="C",
                        help="write only t, q and tau, with q quantised to 2*pi/C rad like an encoder "
                        f"(C up to {ENCODER_COUNT_LIMIT:,})")
    for field, help_text in (("true_coulomb", "the joint's Coulomb friction FC*sign(qd), 0 to 10 N m; default 0"),
                             ("true_bias", "the torque sensor reads TAU0 too much, -10 to 10 N m; default 0"),
                             ("true_angle_offset", "the logged angle is q_true - Q0, -0.5 to 0.5 rad; default 0")):
        parser.add_argument(f"--{field.replace('_', '-')}", dest=field, type=setting_type(field), default=0.0,
                            metavar={"true_coulomb": "FC", "true_bias": "TAU0"}.get(field, "Q0"), help=help_text)
    motors = parser.add_argument_group(
        "motor current or voltage instead of torque",
        "Write the effort a motor would take for the joint's torque: --effort current with --kt (current = "
        "torque / (gear x kt x efficiency)), or --effort voltage with a motor (voltage = torque / c + gear/Kv x qd, "
        "c = efficiency x gear x motors x kt / R); the column is named effort, to fit with the same --effort.")
    motors.add_argument("--effort", choices=("torque", "current", "voltage"), default=None,
                        help="what the effort column holds: joint torque (N m, the default), motor current (A) or "
                        "motor voltage (V)")
    for flag, kind, metavar, help_text in (
            ("--gear", positive_number, "G", "motor turns per joint turn; default 1"),
            ("--kt", positive_number, "N_M_PER_A", "torque constant of the current, for --effort current"),
            ("--efficiency", efficiency_number, "E", "the gearbox's efficiency, 0 < E <= 1; default 1"),
            ("--motor", str, "NAME", "one of WPILib's DCMotor (NEO, Kraken X60, ...), for --effort voltage"),
            ("--motor-count", whole_number(1), "N", "motors driving the joint; default 1"),
            ("--motor-r", positive_number, "OHM", "a motor of your own: resistance"),
            ("--motor-kt", positive_number, "N_M_PER_A", "a motor of your own: torque constant"),
            ("--motor-kv", positive_number, "RAD_PER_S_PER_V", "a motor of your own: speed constant")):
        motors.add_argument(flag, type=kind, default=None, metavar=metavar, help=help_text)
    parser.set_defaults(effort_scale=None, motor_inertia=None, gains=None)
    parser.add_argument("--out", required=True, metavar="FILE", help="the CSV file to write")
    parser.add_argument("--force", action="store_true", help="replace FILE if it exists (only a regular file: never a symlink, a FIFO, a device or a folder)")


def timing(samples: int | None, rate: float | None, duration: float | None) -> tuple[int, float]:
    """Resolve (samples, duration) from the given subset of samples, rate and duration; UserError on conflict."""
    if rate is not None:
        if duration is None:
            duration = DURATION if samples is None else (samples - 1) / rate
            if duration > DURATION_LIMIT:
                raise UserError(
                    f"--samples {samples} at --rate {rate:g} Hz span {duration:g} s; "
                    f"at most {DURATION_LIMIT:g} s (--duration) is allowed"
                )
        intervals = duration * rate
        whole = round(intervals)
        if abs(intervals - whole) > 1e-9 * max(1.0, intervals):
            raise UserError(
                f"--duration {duration:g} s at --rate {rate:g} Hz is {intervals:g} sample intervals, "
                "not a whole number"
            )
        if samples is not None and samples != whole + 1:
            raise UserError(
                f"--samples {samples} contradicts --rate {rate:g} Hz over {duration:g} s, "
                f"which gives {whole + 1} samples; give two of the three"
            )
        samples = whole + 1
        try:
            check_setting("samples", samples)
        except SettingsError as error:
            raise UserError(f"--rate {rate:g} Hz over {duration:g} s gives {error}") from None
    return (SETTING_DEFAULTS["samples"] if samples is None else samples), (DURATION if duration is None else duration)


def motor_effort(args: argparse.Namespace, tau, qd):
    """(the logged effort, a comment's words) for --effort current or voltage, or (None, '') for torque; UserError
    on a bad mix of the motor options."""
    from .effort_arguments import effort_reading, motor_drive

    kind = args.effort or "torque"
    reading = effort_reading(args)
    drive = motor_drive(args)
    if kind == "torque":
        if drive is not None:
            raise UserError("--motor: only with --effort voltage (a torque log needs no motor)")
        return None, ""
    if kind == "current":
        if drive is not None:
            raise UserError("--motor: only with --effort voltage (a current log needs --kt)")
        factor = reading.current_factor
        return tau / factor, (f"; effort = motor current (A) = torque / {factor:.6g} N m/A (gear {reading.gear:g}, "
                              f"kt {reading.kt:g} N m/A, efficiency {reading.efficiency:g})")
    if drive is None:
        raise UserError("--effort voltage needs a motor: --motor NAME (WPILib's DCMotor), or --motor-r, --motor-kt "
                        "and --motor-kv")
    return (tau / drive.torque_per_volt + drive.back_emf * qd,
            f"; effort = motor voltage (V) of {drive.description()}")


def run(args: argparse.Namespace) -> int:
    """Write the log; print one line saying what was written; exit status 0."""
    import numpy as np  # numpy and the numeric modules load only to run

    from ..files import ExportError, atomic_output
    from ..model.truth import TrueJoint
    from ..text_safety import shown_name
    from ..synthetic.motions import ALL_MOTIONS
    from ..synthetic.noise import torque_noise

    samples, duration = timing(args.samples, args.rate, args.duration)
    t = np.linspace(0.0, duration, samples)
    if args.jitter:
        shift = np.random.default_rng(args.seed).uniform(-args.jitter, args.jitter, samples)
        shift[[0, -1]] = 0.0
        t = t + shift * (duration / (samples - 1))
    motion = ALL_MOTIONS[args.motion] if args.motion_file is None else motion_from_file(args.motion_file)
    states = motion.states(t)
    joint = TrueJoint(coulomb=args.true_coulomb, bias=args.true_bias, angle_offset=args.true_angle_offset)
    tau = joint.measured_torque(states.q, states.qd, states.qdd) + torque_noise(args.noise, samples, args.seed)
    q = joint.logged_angle(states.q)
    effort, effort_text = motor_effort(args, tau, states.qd)
    column = "tau" if effort is None else "effort"
    tau = tau if effort is None else effort
    if args.encoder_counts is None:
        names, table = (*FULL_COLUMNS[:-1], column), np.column_stack([t, q, states.qd, states.qdd, tau])
    else:
        step = 2 * math.pi / args.encoder_counts
        names, table = (*ENCODER_COLUMNS[:-1], column), np.column_stack([t, np.round(q / step) * step, tau])
    if not np.isfinite(table).all():  # the limits above should make this impossible: never write such a row
        raise UserError("the simulated log would hold values that are not finite numbers; nothing written")
    truth = joint.description()
    quantised = "" if args.encoder_counts is None else f", q quantised to {args.encoder_counts} counts/rev"
    if args.jitter:
        quantised += f", sampling instants jittered by up to {args.jitter:g} steps"
    comment = (
        f"# jointid simulate: {motion.name} motion, {samples} samples over {duration:g} s{quantised}, "
        f"uniform torque noise bound {args.noise:g} N m, seed {args.seed}; true {truth}{effort_text}\n"
    )
    try:
        with atomic_output(args.out, overwrite=args.force) as handle:
            handle.write(comment)
            # 17 significant digits: reading the file back gives the same doubles.
            np.savetxt(handle, table, delimiter=",", fmt="%.17g", header=",".join(names), comments="")
    except ExportError as error:
        hint = " (add --force to replace it)" if "already exists" in str(error) else ""
        raise UserError(f"{error}{hint}") from None
    print(f"Wrote {shown_name(args.out)}: {samples} samples of {', '.join(names)} ({motion.name} motion, "
          f"{duration:g} s).")
    return ExitStatus.SUCCESS
