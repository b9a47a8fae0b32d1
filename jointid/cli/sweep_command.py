"""`jointid sweep`: the same experiment under K noise seeds, with statistics of every estimate."""

from __future__ import annotations

import argparse

from ..present.documents import sweep_document
from ..present.tables import sweep_text
from ..sweep import DEFAULT_SEED_COUNT, SEED_COUNT_LIMITS, run_sweep
from .arguments import add_model_argument, add_settings_arguments, settings_from, whole_number
from .output import print_json

NAME = "sweep"


def add_parser(subparsers) -> None:
    """Attach the `sweep` subcommand."""
    parser = subparsers.add_parser(
        NAME,
        help="repeat one experiment over many noise seeds and summarise the estimates",
        description="Fit the chosen motion, noise and samples for K seeds starting at --seed "
        "(wrapping past 4294967295 to 0), with one factorisation for all of them; print the mean, "
        "standard deviation and 5/50/95 % percentiles of every parameter and both RMSEs, the share of "
        "seeds failing a sign check, and the empirical standard deviations beside the expected ones.",
    )
    add_settings_arguments(parser)
    add_model_argument(parser)
    low, high = SEED_COUNT_LIMITS
    parser.add_argument(
        "--seeds",
        type=whole_number(*SEED_COUNT_LIMITS),
        default=DEFAULT_SEED_COUNT,
        metavar="K",
        help=f"number of seeds, {low} to {high:,}; default {DEFAULT_SEED_COUNT}",
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")


def run(args: argparse.Namespace) -> int:
    """Run the sweep and print text or JSON; exit status 0."""
    sweep = run_sweep(settings_from(args), args.seeds)
    if args.json:
        print_json(sweep_document(sweep))
    else:
        print(sweep_text(sweep))
    return 0
