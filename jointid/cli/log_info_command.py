"""`jointid log-info`: the entries of a WPILib data log, and the tests of any SysId routine it holds."""

from __future__ import annotations

import argparse

from .arguments import UserError
from .commands import SUBCOMMANDS
from .exit_status import ExitStatus

NAME = "log-info"


def add_parser(subparsers) -> None:
    """Attach the `log-info` subcommand."""
    parser = subparsers.add_parser(
        NAME,
        help=SUBCOMMANDS[NAME].summary,
        description="Read a WPILib data log (.wpilog; needs pip install 'jointid[wpilib]') and print every entry "
        "with its type, record count, mean rate and the unit its metadata names; then, when the log is a SysId "
        "routine log (sysid-test-state-<routine> with voltage-, position- and velocity-<motor>-<routine> "
        "entries), its motor's entries and the test runs `jointid fit --wpilog` fits.",
    )
    parser.add_argument("path", metavar="LOG.wpilog", help="the data log")
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")


def run(args: argparse.Namespace) -> int:
    """Survey the log and print text or JSON; exit status 0 (2 with one line for an unreadable log)."""
    from ..logs.table import LogError
    from ..logs.wpilog import (
        wpilog_info,  # numpy and wpiutil only now, so `jointid --help` stays light
    )
    from ..present.wpiloginfo import wpilog_info_text
    from .output import print_json

    try:
        info = wpilog_info(args.path)
    except LogError as error:
        raise UserError(str(error)) from None
    if args.json:
        print_json(info.to_dict())
    else:
        print(wpilog_info_text(info))
    return ExitStatus.SUCCESS
