"""`jointid export`: the identified joint as a MuJoCo model (MJCF) and a URDF robot, for simulators.

It fits as `jointid fit` does (the same synthetic settings, --csv runs, --bag,
--model flags), or takes a fit's JSON (--from-json). I and h = m r do not
reveal the mass, the centre of mass and the inertia about it apart, so the
export needs --mass (or --com-distance) and derives the rest; a link that no
body can be is refused in one line (jointid.model.rigid_link).
"""

from __future__ import annotations

import argparse
import os
import re
import sys

from .arguments import (
    UserError,
    add_model_argument,
    add_settings_arguments,
    finite_float,
    positive_number,
)
from .commands import SUBCOMMANDS
from .exit_status import ExitStatus
from .log_arguments import LOG_ONLY_FLAGS, SETTING_FLAGS, add_log_arguments, has_log

NAME = "export"

FORMAT_FLAGS = ("mujoco", "urdf")
"""The file flags, in the order the files are written and named."""

_XML_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_.-]{0,63}")


def xml_name(text: str) -> str:
    """An argparse type for --name: a name MJCF and URDF take as it is (a letter or _, then letters, digits, _ . -)."""
    if _XML_NAME.fullmatch(text) is None:
        raise argparse.ArgumentTypeError(f"must start with a letter or _ and hold only letters, digits, _, . and -, "
                                         f"at most 64 characters; got {text!r}")
    return text


def nonnegative_number(text: str) -> float:
    """An argparse type for a finite number of 0 or more."""
    value = finite_float(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be a finite number of 0 or more; got {text!r}")
    return value


def add_parser(subparsers) -> None:
    """Attach the `export` subcommand."""
    parser = subparsers.add_parser(
        NAME,
        help=SUBCOMMANDS[NAME].summary,
        description="Fit as `jointid fit` does (or read a fit's JSON with --from-json) and write one rigid link on "
        "a hinge: the joint's damping B, friction Fc (frictionloss in MJCF) and armature, and the link's mass, "
        "centre of mass and inertia about it. I and h = m r do not reveal the mass, so give --mass (or "
        "--com-distance): r = h/m and the inertia about the centre of mass I - h²/m follow, and a link no body can "
        "be (that inertia not positive, a centre of mass beyond --length) is refused. Gravity is along -z; the "
        "joint's 0 and direction are jointid's q (0 horizontal, counter-clockwise) or, with --zero/--clockwise, "
        "the log's. Files are written atomically and never over an existing one without --force.",
    )
    files = parser.add_argument_group("files (at least one)")
    files.add_argument("--mujoco", metavar="FILE.xml", help="write a MuJoCo model (MJCF) here")
    files.add_argument("--urdf", metavar="FILE.urdf", help="write a URDF robot here")
    files.add_argument("--force", action="store_true",
                       help="replace the files if they exist (only regular files: never a symlink, a FIFO, a device "
                       "or a folder)")
    files.add_argument("--name", type=xml_name, default="joint", metavar="NAME",
                       help="the joint's name; its link is NAME_link, the URDF's fixed base NAME_base, the MJCF's "
                       "motor NAME_motor; default joint")
    link = parser.add_argument_group("the link (I and h do not reveal its mass: give --mass or --com-distance)")
    split = link.add_mutually_exclusive_group(required=True)
    split.add_argument("--mass", type=positive_number, metavar="KG",
                       help="the link's mass (kg): the centre of mass lies h/m from the axis")
    split.add_argument("--com-distance", type=positive_number, metavar="M",
                       help="the centre of mass's distance from the axis (m): the mass is h/r")
    link.add_argument("--length", type=positive_number, metavar="M",
                      help="the link's length (m): a centre of mass beyond it is refused; the drawn rod reaches it")
    link.add_argument("--armature", type=nonnegative_number, default=0.0, metavar="KGM2",
                      help="the part of I that is a motor's reflected rotor inertia (gear² x rotor inertia, kg m²): "
                      "the MJCF's joint armature, taken out of the link's inertia (URDF, which has no armature, keeps "
                      "it in the link's moment about the axis); default 0")
    parser.add_argument("--from-json", metavar="FIT.json",
                        help="take the parameters from this fit's JSON (`jointid fit ... --json > FIT.json`, one fit "
                        "or several runs) instead of fitting")
    parser.add_argument("--json", action="store_true",
                        help="print one JSON object (the parameters, the link, the files) instead of text")
    parser.add_argument("--check", action="store_true",
                        help="load the written MJCF in MuJoCo and confirm its joint inertia and gravity torque are "
                        "the identified I and h g (needs pip install 'jointid[mujoco]')")
    add_settings_arguments(parser)
    add_model_argument(parser)
    add_log_arguments(parser)


def run(args: argparse.Namespace) -> int:
    """Fit (or read the fit's JSON), derive the link, write the files, print what was written; exit status 0."""
    written = {kind: getattr(args, kind) for kind in FORMAT_FLAGS if getattr(args, kind) is not None}
    if not written:
        raise UserError("give --mujoco FILE.xml, --urdf FILE.urdf or both: the files to write")
    if len({os.path.abspath(path) for path in written.values()}) < len(written):
        raise UserError("--mujoco and --urdf name the same file; give each its own")
    if args.check:
        if "mujoco" not in written:
            raise UserError("--check loads the MJCF in MuJoCo: add --mujoco FILE.xml")
        from ..studies.mujoco_check import MujocoMissing, import_mujoco

        try:
            import_mujoco()  # before fitting and writing: a missing extra leaves nothing behind
        except MujocoMissing as error:
            raise UserError(str(error)) from None
    identified = _identified(args)
    from ..files import ExportError, write_texts
    from ..logs.conventions import AngleConvention
    from ..model.rigid_link import LinkError, split_link
    from ..present.simulators import (
        convention_text,
        export_document,
        export_text,
        mjcf_text,
        mujoco_check_text,
        undetermined_warning,
        urdf_text,
    )

    parameters = identified.parameters
    missing = [name for name in ("I", "h", "B") if name not in parameters]
    if missing:
        raise UserError(f"the fit has no {', '.join(missing)}: nothing to export")
    convention = AngleConvention(identified.zero, identified.clockwise)
    try:
        link = split_link(parameters["I"], parameters["h"], parameters["B"], parameters.get("Fc", 0.0),
                          parameters.get("q0", 0.0), mass=args.mass, com_distance=args.com_distance,
                          length=args.length, armature=_armature(args, identified), zero_offset=convention.offset,
                          axis_sign=convention.sign)
    except LinkError as error:
        raise UserError(str(error)) from None
    writers = {"mujoco": mjcf_text, "urdf": urdf_text}
    texts = {path: writers[kind](link, args.name, identified.source) for kind, path in written.items()}
    try:
        write_texts(texts, overwrite=args.force)
    except ExportError as error:
        hint = " (add --force to replace it)" if "already exists" in str(error) else ""
        raise UserError(f"{error}{hint}") from None
    undetermined = identified.not_determined(("I", "h", "B", "Fc", "q0"))
    if undetermined:
        print(undetermined_warning(undetermined), file=sys.stderr)
    check = _mujoco_check(written["mujoco"], link) if args.check else None
    if args.json:
        from .output import print_json

        extra = {} if check is None else {"mujoco_check": {
            "version": check.version, "joint_inertia": check.joint_inertia, "gravity_torque": check.gravity_torque,
            "agrees": check.agrees}}
        print_json({**export_document(link, identified.parameters, identified.model, identified.source, written,
                                      undetermined), **extra})
    else:
        print(export_text(link, parameters, identified.model, written, mass_given=args.mass is not None,
                          convention=convention_text(identified.zero, identified.clockwise)))
        if check is not None:
            print(mujoco_check_text(check, written["mujoco"]))
    return ExitStatus.ERROR if check is not None and not check.agrees else ExitStatus.SUCCESS


def _armature(args: argparse.Namespace, identified) -> float:
    """--armature, or else the motor's reflected rotor inertia a voltage fit's --motor-inertia gave (kg m²)."""
    if args.armature == 0.0 and identified.reflected_inertia is not None:
        return identified.reflected_inertia
    return args.armature


def _mujoco_check(path: str, link):
    """MuJoCo's reading of the written MJCF (studies.mujoco_check); UserError when MuJoCo refuses the file."""
    from ..studies.mujoco_check import check_mujoco

    try:
        return check_mujoco(path, link)
    except ValueError as error:
        raise UserError(str(error)) from None


def _identified(args: argparse.Namespace):
    """The fit's parameters: from --from-json (refusing the flags that would fit), or from fitting as `fit`."""
    from .fit_source import identified_from_fit, identified_from_json

    if args.from_json is None:
        return identified_from_fit(args)
    fitting = [f"--{name.replace('_', '-')}" for name in (*SETTING_FLAGS, *LOG_ONLY_FLAGS, "model", "motion_file")
               if getattr(args, name, None) not in (None, False)]
    fitting += ["--constrained"] if args.constrained else []
    if has_log(args):
        fitting.insert(0, "--csv" if getattr(args, "csv", None) is not None else "--bag")
    if fitting:
        raise UserError(f"{', '.join(fitting)}: --from-json takes the fit from its file; drop them (or drop "
                        "--from-json to fit here)")
    return identified_from_json(args.from_json)
