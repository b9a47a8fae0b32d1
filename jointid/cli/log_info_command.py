"""`jointid log-info`: the entries of a WPILib data log, and the tests of any SysId routine it holds."""

from __future__ import annotations

import argparse

from .file_survey import add_survey_parser, print_survey

NAME = "log-info"


def add_parser(subparsers) -> None:
    """Attach the `log-info` subcommand."""
    add_survey_parser(
        subparsers, NAME,
        "Read a WPILib data log (.wpilog; needs pip install 'jointid[wpilib]') and print every entry "
        "with its type, record count, mean rate and the unit its metadata names; then, when the log is a SysId "
        "routine log (sysid-test-state-<routine> with voltage-, position- and velocity-<motor>-<routine> "
        "entries), its motor's entries and the test runs `jointid fit --wpilog` fits.",
        "LOG.wpilog", "the data log")


def run(args: argparse.Namespace) -> int:
    """Survey the log and print text or JSON; exit status 0 (2 with one line for an unreadable log)."""
    from ..logs.wpilog import wpilog_info  # numpy and wpiutil only now, so `jointid --help` stays light
    from ..present.wpiloginfo import wpilog_info_text

    return print_survey(wpilog_info, args.path, wpilog_info_text, args.json)
