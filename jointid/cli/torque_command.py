"""`jointid torque`: inverse dynamics at one state, split into contributions."""

from __future__ import annotations

import argparse
import math

from ..options import TRUE_VALUES
from .arguments import UserError, finite_float
from .commands import SUBCOMMANDS
from .exit_status import ExitStatus
from .output import print_json

NAME = "torque"

PARTS = {
    "inertia": "the inertia torque I*qdd",
    "gravity": "the gravity compensation h*g*cos(q)",
    "damping": "the damping compensation B*qd",
    "total": "the actuator torque",
    "damper_power": "the damper's power B*qd²",
}
"""Each computed value's key and how a message names it."""


def add_parser(subparsers) -> None:
    """Attach the `torque` subcommand."""
    parser = subparsers.add_parser(
        NAME,
        help=SUBCOMMANDS[NAME].summary,
        description="Inverse dynamics tau = I*qdd + h*g*cos(q) + B*qd at one state, with the "
        "power B*qd² that the damper dissipates.",
    )
    parser.add_argument("--q", type=finite_float, required=True, metavar="Q",
                        help="joint angle from +x, counter-clockwise (rad, or deg with --deg)")
    parser.add_argument("--qd", type=finite_float, required=True, metavar="QD",
                        help="joint velocity (rad/s)")
    parser.add_argument("--qdd", type=finite_float, required=True, metavar="QDD",
                        help="joint acceleration (rad/s²)")
    parser.add_argument("--deg", action="store_true", help="read --q in degrees")
    inertia, mass_moment, damping = (TRUE_VALUES[name] for name in ("I", "h", "B"))
    parser.add_argument("--I", dest="I", type=finite_float, default=inertia, metavar="I",
                        help=f"inertia about the joint (kg m²); default {inertia}")
    parser.add_argument("--h", dest="h", type=finite_float, default=mass_moment, metavar="H",
                        help=f"gravity mass moment m*r (kg m); default {mass_moment}")
    parser.add_argument("--B", dest="B", type=finite_float, default=damping, metavar="B",
                        help=f"viscous damping (N m s/rad); default {damping}")
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")


def run(args: argparse.Namespace) -> int:
    """Compute and print the breakdown; exit status 0."""
    import numpy as np  # numpy and the numeric modules load only to run

    from ..model.breakdown import torque_breakdown
    from ..present.text import format_number

    q = math.radians(args.q) if args.deg else args.q
    with np.errstate(over="ignore", invalid="ignore"):  # checked below, with a message naming the value
        parts = torque_breakdown(q, args.qd, args.qdd, (args.I, args.h, args.B))
        values = {name: float(getattr(parts, name)) for name in PARTS}
    for name, value in values.items():
        if not math.isfinite(value):
            raise UserError(f"{PARTS[name]} overflows double precision (beyond ±1.8e308); give smaller values")
    if args.json:
        state = {"q": q, "qd": args.qd, "qdd": args.qdd}
        parameters = {"I": args.I, "h": args.h, "B": args.B}
        print_json({"state": state, "parameters": parameters, **values})
        return ExitStatus.SUCCESS
    angle = f"{format_number(args.q)} deg = {format_number(q)} rad" if args.deg else f"{format_number(q)} rad"
    print(f"State: q = {angle}, qd = {format_number(args.qd)} rad/s, qdd = {format_number(args.qdd)} rad/s²")
    print(f"Parameters: I = {args.I:g} kg m², h = {args.h:g} kg m, B = {args.B:g} N m s/rad")
    rows = [
        ("Inertia            I*qdd", values["inertia"], "N m"),
        ("Gravity comp.      h*g*cos(q)", values["gravity"], "N m"),
        ("Damping comp.      B*qd", values["damping"], "N m"),
        ("Actuator torque", values["total"], "N m"),
        ("Damper dissipates  B*qd²", values["damper_power"], "W"),
    ]
    for label, value, unit in rows:
        print(f"{label:<32}{format_number(value):>12} {unit}")
    return ExitStatus.SUCCESS
