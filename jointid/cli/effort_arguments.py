"""The options saying what a log's effort measured and which motor drove the joint: --effort, --gear, --kt,
--efficiency, --motor (or --motor-r/--motor-kt/--motor-kv), --motor-count, --motor-inertia, and --gains.

--effort-scale K multiplies the logged effort into its kind's unit: N m for torque (the default), V for voltage
(a log of duty cycle times the battery's 12 V, say). A current log's scale is --gear x --kt x --efficiency
instead, so --effort-scale with --effort current is refused rather than combined.
"""

from __future__ import annotations

import argparse

from ..options import MECHANISMS
from .arguments import UserError, positive_number, whole_number

EFFORT_FLAGS = ("effort", "gear", "kt", "efficiency", "motor", "motor_r", "motor_kt", "motor_kv", "motor_count",
                "motor_inertia", "gains")
"""Options that mean something only with a log."""

CUSTOM_MOTOR_FLAGS = ("motor_r", "motor_kt", "motor_kv")


def efficiency_number(text: str) -> float:
    """An argparse type for --efficiency: greater than 0 and at most 1."""
    value = positive_number(text)
    if value > 1:
        raise argparse.ArgumentTypeError(f"must be a number greater than 0 and at most 1; got {text!r}")
    return value


def add_effort_arguments(group) -> None:
    """Add the effort kind, gearing, motor and gains options to a log group."""
    group.add_argument("--effort", choices=("torque", "current", "voltage"), default=None,
                       help="what the log's effort (tau) column measured: joint torque in N m (the default), motor "
                       "current in A (turned into torque = gear x kt x efficiency x current: needs --kt), or motor "
                       "voltage in V (fitted in volts: kA, kG, kV, kS, WPILib's arm feedforward gains)")
    group.add_argument("--gear", type=positive_number, default=None, metavar="G",
                       help="motor turns per joint turn (the reduction), for --effort current or a motor; default 1")
    group.add_argument("--kt", type=positive_number, default=None, metavar="N_M_PER_A",
                       help="torque constant (N m/A) of the logged current, for --effort current")
    group.add_argument("--efficiency", type=efficiency_number, default=None, metavar="E",
                       help="the gearbox's efficiency, 0 < E <= 1, for --effort current or a motor; default 1")
    group.add_argument("--motor", metavar="NAME",
                       help="the joint's motor, one of WPILib's DCMotor (NEO, NEO 550, NEO Vortex, Falcon 500, "
                       "Kraken X60, CIM, MiniCIM, 775pro, ...): gives the physical I, h, B, Fc behind a voltage "
                       "log's gains, and converts a torque log's to gains (--gains)")
    group.add_argument("--motor-r", type=positive_number, default=None, metavar="OHM",
                       help="a motor of your own: its winding resistance (ohm; with --motor-kt and --motor-kv)")
    group.add_argument("--motor-kt", type=positive_number, default=None, metavar="N_M_PER_A",
                       help="a motor of your own: its torque constant (N m/A)")
    group.add_argument("--motor-kv", type=positive_number, default=None, metavar="RAD_PER_S_PER_V",
                       help="a motor of your own: its speed constant ((rad/s)/V, WPILib's DCMotor.Kv; the back-EMF "
                       "is speed/Kv)")
    group.add_argument("--motor-count", type=whole_number(1), default=None, metavar="N",
                       help="motors driving the joint together; default 1")
    group.add_argument("--motor-inertia", type=positive_number, default=None, metavar="KG_M2",
                       help="one rotor's inertia (kg m²), to separate the rotors' reflected inertia (count x gear² "
                       "x it) from the load's; WPILib does not publish it")
    group.add_argument("--gains", choices=("wpilib",), default=None,
                       help="also print the gains a controller takes: the mechanism's WPILib feedforward "
                       "(SimpleMotorFeedforward kS, kV, kA; ElevatorFeedforward and ArmFeedforward with kG) in the "
                       "log's own units, with errors, verdicts, SysId's direction of regression and a "
                       "Java/C++/Python constructor (needs a voltage log, or a motor to convert a torque log)")
    group.add_argument("--mechanism", choices=MECHANISMS, default=None,
                       help="what a voltage log's routine characterised: simple (a flywheel, roller or drive: "
                       "kS, kV, kA), elevator (+ a constant kG) or arm (+ kG cos of the angle, and its offset); "
                       "default: chosen from a data log by BIC, the note says why (a CSV voltage log: arm)")


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")


def effort_reading(args: argparse.Namespace):
    """The logs.effort.EffortReading of --effort, --gear, --kt, --efficiency; UserError on a bad mix."""
    from ..logs.effort import EffortReading

    kind = getattr(args, "effort", None) or "torque"
    if kind == "current":
        if args.kt is None:
            raise UserError("--effort current needs --kt N_M_PER_A, the motor's torque constant "
                            "(torque = gear x kt x efficiency x current)")
        if args.effort_scale is not None:
            raise UserError("--effort-scale: not with --effort current, whose torque per ampere is --gear x --kt x "
                            "--efficiency; drop it")
    elif args.kt is not None:
        raise UserError("--kt: only with --effort current (a motor's own constant is --motor-kt)")
    has_motor = args.motor is not None or any(getattr(args, name) is not None for name in CUSTOM_MOTOR_FLAGS)
    if kind != "current" and not has_motor:
        stray = [_flag(name) for name in ("gear", "efficiency") if getattr(args, name) is not None]
        if stray:
            raise UserError(f"{', '.join(stray)}: only with --effort current or a motor (--motor NAME, or "
                            "--motor-r/--motor-kt/--motor-kv)")
    gear = 1.0 if args.gear is None else args.gear
    efficiency = 1.0 if args.efficiency is None else args.efficiency
    if kind == "current":
        return EffortReading("current", 1.0, gear, args.kt, efficiency)
    return EffortReading(kind)


def motor_drive(args: argparse.Namespace):
    """The model.motors.MotorDrive of --motor (or --motor-r/-kt/-kv), --motor-count, --gear, --efficiency,
    --motor-inertia, or None without a motor; UserError on a bad mix or an unknown motor."""
    custom = {name: getattr(args, name) for name in CUSTOM_MOTOR_FLAGS}
    given = [name for name, value in custom.items() if value is not None]
    if args.motor is not None and given:
        raise UserError(f"--motor {args.motor} and {', '.join(map(_flag, given))}: give a WPILib motor by name or "
                        "your own motor's constants, not both")
    if given and len(given) < 3:
        missing = [_flag(name) for name in CUSTOM_MOTOR_FLAGS if name not in given]
        raise UserError(f"a motor of your own needs {', '.join(missing)} as well (--motor-r OHM --motor-kt N_M_PER_A "
                        "--motor-kv RAD_PER_S_PER_V)")
    if args.motor is None and not given:
        stray = [_flag(name) for name in ("motor_count", "motor_inertia") if getattr(args, name) is not None]
        if stray:
            raise UserError(f"{', '.join(stray)}: only with a motor (--motor NAME, or --motor-r/--motor-kt/--motor-kv)")
        return None
    from ..model.motors import MotorDrive, UnknownMotor, motor_named  # only with a motor: a few ms of each start

    count = 1 if args.motor_count is None else args.motor_count
    gear = 1.0 if args.gear is None else args.gear
    efficiency = 1.0 if args.efficiency is None else args.efficiency
    if args.motor is not None:
        try:
            motor = motor_named(args.motor)
        except UnknownMotor as error:
            raise UserError(f"--motor: {error}") from None
        return MotorDrive.of(motor, count, gear, efficiency, args.motor_inertia)
    return MotorDrive("custom", args.motor_r, args.motor_kt, args.motor_kv, count, gear, efficiency,
                      args.motor_inertia)


def check_gains_request(args: argparse.Namespace) -> None:
    """UserError when --gains wpilib cannot be given: a torque (or current) log without a motor."""
    if getattr(args, "gains", None) is None:
        return
    if (args.effort or "torque") != "voltage" and motor_drive(args) is None:
        raise UserError("--gains wpilib needs volts: fit a voltage log (--effort voltage), or give the motor "
                        "(--motor NAME --gear G, or --motor-r/--motor-kt/--motor-kv) to convert this torque log")


def effort_extras(args: argparse.Namespace, logs):
    """(text paragraphs, JSON fields) the motor and --gains add to the output of a log's fit (or of several runs
    pooled); UserError when the fit gives none."""
    drive = motor_drive(args)
    paragraphs, fields = [], {}
    if drive is None and getattr(args, "gains", None) != "wpilib":
        return paragraphs, fields
    from ..studies.gains import GainsError, arm_gains, motor_parameters  # only when asked: a few ms of each start

    model = (logs.runs[0] if hasattr(logs, "runs") else logs).result.model
    try:
        if drive is not None and not model.effort.is_torque:
            from ..present.gains import motor_object, motor_text

            motor = motor_parameters(logs, drive)
            paragraphs.append(motor_text(motor))
            fields["motor"] = motor_object(motor)
        elif drive is not None:
            from ..present.gains import drive_object

            paragraphs.append(f"Motor: {drive.description()}; --gains wpilib turns this torque fit into the gains "
                              "of a voltage.")
            fields["motor"] = drive_object(drive)
        if getattr(args, "gains", None) == "wpilib":
            from ..present.gains import gains_object, gains_text

            gains = arm_gains(logs, drive)
            paragraphs.append(gains_text(gains))
            fields["gains"] = gains_object(gains)
    except GainsError as error:
        raise UserError(str(error)) from None
    return paragraphs, fields
