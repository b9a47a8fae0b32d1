"""`jointid matrix`: the cross-excitation table of prediction errors."""

from __future__ import annotations

import argparse

from .arguments import add_model_argument, add_settings_arguments, settings_from
from .commands import SUBCOMMANDS
from .exit_status import ExitStatus
from .output import print_json

NAME = "matrix"


def add_parser(subparsers) -> None:
    """Attach the `matrix` subcommand."""
    parser = subparsers.add_parser(
        NAME,
        help=SUBCOMMANDS[NAME].summary,
        description="Fit rich, slow and holds at the given noise, samples and seed (--motion is "
        "ignored: every motion gets a row) and predict the noiseless torque of the rich and slow "
        "motions (at the same sample count) and of the 16 validation states. An entry on a row's "
        "own motion is training data, not a held-out test.",
    )
    add_settings_arguments(parser)
    add_model_argument(parser)
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")


def run(args: argparse.Namespace) -> int:
    """Build the table and print text or JSON; exit status 0."""
    from ..present.documents import matrix_document
    from ..present.tables import matrix_text
    from ..studies.cross_excitation import (
        cross_excitation,  # numpy and the numeric modules load only to run
    )

    table = cross_excitation(settings_from(args))
    if args.json:
        print_json(matrix_document(table))
    else:
        print(matrix_text(table))
    return ExitStatus.SUCCESS
