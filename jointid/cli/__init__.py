"""The `jointid` command line: subcommands for fitting and inverse dynamics.

Each subcommand lives in its own module with `add_parser(subparsers)` and
`run(args) -> int`. With no subcommand, `jointid` opens the terminal explorer.
Errors a user can cause print one line on stderr and exit with status 2.
"""

from __future__ import annotations

import argparse
import gc
import sys
from importlib import import_module

from .arguments import (
    OneLineParser,
    UserError,
    add_model_argument,
    add_settings_arguments,
    print_error_line,
)
from .commands import SUBCOMMANDS
from .exit_status import ExitStatus
from .floating_point import strict_arithmetic
from .log_arguments import add_log_arguments
from .output import end_process, output_error_line
from .version import VersionAction


def subcommand(name: str):
    """The module that defines subcommand `name` (a key of SUBCOMMANDS)."""
    return import_module(f".{SUBCOMMANDS[name].module}", __name__)


def build_parser(chosen: str | None = None) -> OneLineParser:
    """The top-level parser with every subcommand attached: `chosen`'s with all its flags, the others as their
    help line, taking any words (enough to list them and to find which one a command line names)."""
    parser = OneLineParser(
        prog="jointid",
        # Whole option names only here: with --heldout, torque's --h would be read as an ambiguous prefix.
        allow_abbrev=False,
        description=(
            "Identify a rotating joint's inertia I, gravity mass moment h and viscous damping B "
            "from motion and torque: tau = I*qdd + h*g*cos(q) + B*qd. "
            "With no subcommand, open the terminal explorer at the given settings, or on a --csv, --bag or --wpilog "
            "log."
        ),
    )
    parser.add_argument("--version", action=VersionAction,
                        help="print the versions of jointid and its stack, and whether the explorer's "
                             "third-party adapters apply to them, then exit")
    add_settings_arguments(parser)
    add_model_argument(parser)
    add_log_arguments(parser)
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=OneLineParser)
    for name, command in SUBCOMMANDS.items():
        if name == chosen:
            subcommand(name).add_parser(subparsers)
        else:
            subparsers.add_parser(name, help=command.summary, add_help=False).add_argument(
                "words", nargs=argparse.REMAINDER)
    return parser


def parse(argv: list[str]):
    """The arguments' namespace (`command` None for the explorer), with the words as typed in `argv`: `serve`
    hands the explorer's flags on to each session as they were written."""
    parser = build_parser()
    chosen = parser.parse_known_args(argv)[0].command  # argparse's own reading of which word is the command
    args = (parser if chosen is None else build_parser(chosen)).parse_args(argv)
    args.argv = list(argv)
    return args


def console_script(explorer=None) -> None:
    """The `jointid` console script (tui/command.py) and `python -m jointid`: main(), which ends the process
    itself after a subcommand (see end_process); the explorer returns, and Python's own exit closes what it
    opened. `explorer` is as for main().

    The cyclic garbage collector is off until a command that lasts (the explorer, `serve`, `watch`) starts: a
    command that ends makes few reference cycles (the peak memory of fit, compare, report and design grew by at most
    0.8 % without it), while collecting walks every object its imports built and frees almost none: 37-52 ms of a
    1e6-row `jointid fit --csv` (benchmarks/README.md, 2026-11-29 08:15-08:55).
    """
    gc.disable()
    sys.exit(main(end_after_subcommand=True, explorer=explorer))


def main(argv: list[str] | None = None, *, end_after_subcommand: bool = False, explorer=None) -> int:
    """Parse arguments, run the chosen subcommand, and return the exit status.

    With `end_after_subcommand`, a subcommand that finishes ends the process (end_process) instead of returning.
    `explorer` is the terminal explorer's entry function, for no subcommand (see explorer_command); None finds
    it through its entry point.
    """
    argv = sys.argv[1:] if argv is None else argv
    try:
        args = parse(argv)
        args.argv = list(argv)  # as typed, for what a report says it was made by
        if args.command is None or SUBCOMMANDS[args.command].lasting:
            gc.enable()  # console_script turned it off for a command that ends
        if args.command is None:
            from .explorer_command import run as run_explorer

            return run_explorer(args, explorer)  # guards its own loading; the app itself must not raise
        with strict_arithmetic():
            status = subcommand(args.command).run(args)
    except UserError as error:
        print_error_line(f"jointid: {error}")
        return ExitStatus.USER_ERROR
    except BrokenPipeError:  # e.g. `jointid fit | head -1`
        sys.stderr.close()
        return ExitStatus.SUCCESS
    except OSError as error:
        if error.filename is not None:  # a file's errors are LogErrors or UserErrors with the file named
            raise
        print(output_error_line(error), file=sys.stderr)  # e.g. printing onto a full disk
        return ExitStatus.USER_ERROR
    except KeyboardInterrupt:
        return ExitStatus.INTERRUPTED
    if end_after_subcommand:
        end_process(status)
    return status
