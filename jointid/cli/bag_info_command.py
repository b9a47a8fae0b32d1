"""`jointid bag-info`: the topics of a ROS bag, and the joints and timing of its JointState topics."""

from __future__ import annotations

import argparse

from .arguments import UserError
from .commands import SUBCOMMANDS
from .exit_status import ExitStatus

NAME = "bag-info"


def add_parser(subparsers) -> None:
    """Attach the `bag-info` subcommand."""
    parser = subparsers.add_parser(
        NAME,
        help=SUBCOMMANDS[NAME].summary,
        description="Read a ROS bag (ROS 1 .bag, ROS 2 folder with sqlite3 or MCAP storage, or a .mcap/.db3 file; "
        "needs pip install 'jointid[ros]') and print every topic with its type and message count, then for each "
        "sensor_msgs/JointState topic its joints, which of position, velocity and effort each has filled, the "
        "message rate, the median and extreme time steps (jitter) and the duration.",
    )
    parser.add_argument("path", metavar="PATH", help="the bag: a ROS 2 bag folder, or a .bag, .mcap or .db3 file")
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")


def run(args: argparse.Namespace) -> int:
    """Survey the bag and print text or JSON; exit status 0 (2 with one line for an unreadable bag)."""
    from ..logs.bag import (
        bag_info,  # numpy and rosbags only now, so `jointid --help` stays light
    )
    from ..logs.table import LogError
    from ..present.baginfo import bag_info_text
    from .output import print_json

    try:
        info = bag_info(args.path)
    except LogError as error:
        raise UserError(str(error)) from None
    if args.json:
        print_json(info.to_dict())
    else:
        print(bag_info_text(info))
    return ExitStatus.SUCCESS
