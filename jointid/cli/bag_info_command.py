"""`jointid bag-info`: the topics of a ROS bag, and the joints and timing of its JointState topics."""

from __future__ import annotations

import argparse

from .file_survey import add_survey_parser, print_survey

NAME = "bag-info"


def add_parser(subparsers) -> None:
    """Attach the `bag-info` subcommand."""
    add_survey_parser(
        subparsers, NAME,
        "Read a ROS bag (ROS 1 .bag, ROS 2 folder with sqlite3 or MCAP storage, or a .mcap/.db3 file; "
        "needs pip install 'jointid[ros]') and print every topic with its type and message count, then for each "
        "sensor_msgs/JointState topic its joints, which of position, velocity and effort each has filled, the "
        "message rate, the median and extreme time steps (jitter) and the duration.",
        "PATH", "the bag: a ROS 2 bag folder, or a .bag, .mcap or .db3 file")


def run(args: argparse.Namespace) -> int:
    """Survey the bag and print text or JSON; exit status 0 (2 with one line for an unreadable bag)."""
    from ..logs.bag import bag_info  # numpy and rosbags only now, so `jointid --help` stays light
    from ..present.baginfo import bag_info_text

    return print_survey(bag_info, args.path, bag_info_text, args.json)
