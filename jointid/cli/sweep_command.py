"""`jointid sweep`: the same experiment under K noise seeds, with statistics of every estimate."""

from __future__ import annotations

import argparse
import sys

from ..options import DEFAULT_SEED_COUNT, SEED_COUNT_LIMITS, WORK_BUDGET
from .arguments import (
    UserError,
    add_model_argument,
    add_settings_arguments,
    settings_from,
    whole_number,
)
from .commands import SUBCOMMANDS
from .exit_status import ExitStatus
from .output import print_json

NAME = "sweep"

PROGRESS_WORK = 10_000_000
"""Samples x seeds from which a sweep shows its progress on a terminal's stderr (about a second here)."""


def add_parser(subparsers) -> None:
    """Attach the `sweep` subcommand."""
    parser = subparsers.add_parser(
        NAME,
        help=SUBCOMMANDS[NAME].summary,
        description="Fit the chosen motion, noise and samples for K seeds starting at --seed "
        "(wrapping past 4294967295 to 0), with one factorisation for all of them; print the mean, "
        "standard deviation and 5/50/95 % percentiles of every parameter and both RMSEs, the share of "
        "seeds failing a sign check, and the empirical standard deviations beside the expected ones. "
        f"Sweeps of more than {WORK_BUDGET:,} samples x seeds need --force.",
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
    parser.add_argument("--force", action="store_true",
                        help=f"run a sweep of more than {WORK_BUDGET:,} samples x seeds (it can take hours)")


def run(args: argparse.Namespace) -> int:
    """Run the sweep and print text or JSON; exit status 0."""
    from ..present.documents import (
        sweep_document,  # numpy and the numeric modules load only to run
    )
    from ..present.tables import sweep_text
    from ..studies.sweep import run_sweep, sweep_work

    settings = settings_from(args)
    work = sweep_work(settings, args.seeds)
    if work > WORK_BUDGET and not args.force:
        raise UserError(
            f"a sweep of {settings.samples:,} samples x {args.seeds:,} seeds ({work:.2g} sample fits) is over the "
            f"budget of {WORK_BUDGET:.0e}, about 10 s of work; add --force to run it anyway"
        )
    show = sys.stderr.isatty() and work >= PROGRESS_WORK
    try:
        sweep = run_sweep(settings, args.seeds, progress=progress_line if show else None)
    finally:
        if show:  # clear the progress line, also after Ctrl+C
            print("\r\033[K", end="", file=sys.stderr, flush=True)
    if args.json:
        print_json(sweep_document(sweep))
    else:
        print(sweep_text(sweep))
    return ExitStatus.SUCCESS


def progress_line(done: int, total: int) -> None:
    """Rewrite one line on stderr: 'jointid sweep: 42 % (420 of 1,000 seeds)'."""
    print(f"\rjointid sweep: {100 * done // total} % ({done:,} of {total:,} seeds)", end="", file=sys.stderr,
          flush=True)
