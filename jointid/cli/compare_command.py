"""`jointid compare`: fit every model of the ladder on the same data and let BIC choose."""

from __future__ import annotations

import argparse

from ..options import LADDER
from .arguments import UserError, add_settings_arguments, settings_from
from .commands import SUBCOMMANDS
from .exit_status import ExitStatus
from .log_arguments import (
    add_log_arguments,
    exclusion_options,
    filter_options,
    fit_any_logs,
    has_log,
    load_logs,
    log_model,
    several_runs,
    with_default_settings,
)
from .output import print_json

NAME = "compare"


def add_parser(subparsers) -> None:
    """Attach the `compare` subcommand."""
    parser = subparsers.add_parser(
        NAME,
        help=SUBCOMMANDS[NAME].summary,
        description=f"Fit the models {', '.join(LADDER)} on the same training data (a synthetic "
        "experiment or a --csv log) and print one row each: terms, rank, training and held-out RMSE, "
        "BIC = N ln(RSS/N) + k ln N, the condition number of the column-scaled regressor and the worst "
        "determined parameter; then the model BIC prefers and what the others show.",
    )
    add_settings_arguments(parser)
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")
    add_log_arguments(parser)


def run(args: argparse.Namespace) -> int:
    """Compare the ladder on the experiment (or the --csv log) and print text or JSON; exit status 0."""
    from ..present.comparison import comparison_text
    from ..present.documents import comparison_document

    comparison, heading, settings, source = compare(args)
    if args.json:
        print_json(comparison_document(comparison, settings=settings, source=source))
    else:
        print(comparison_text(comparison, heading))
    return ExitStatus.SUCCESS


def compare(args: argparse.Namespace, fitted=None):
    """The ladder on the experiment or the --csv/--bag log: (ladder.Comparison, its heading, the Settings or None,
    the source object or None); UserError (one line) on any problem. `jointid report --compare` uses it too,
    passing the logs it `fitted` already (several runs are compared pooled, from their own fits)."""
    from ..present.notes import low_pass_short_note
    from ..present.text import settings_header
    from ..studies.ladder import compare_experiment  # numpy and the numeric modules load only to run

    if has_log(args) and (fitted is not None and hasattr(fitted, "runs") or several_runs(args)
                          or getattr(args, "wpilog", None) is not None):
        from ..studies.ladder import compare_pooled

        pooled = fitted if fitted is not None else fit_any_logs(args)
        if hasattr(pooled, "runs"):
            names = ", ".join(run.name for run in pooled.runs)
            heading = (f"{len(pooled.runs)} runs pooled ({names}): each run's filtered samples, less what its own "
                       "fit left out, stacked with its own bias; BIC counts every run's samples")
            return compare_pooled(pooled.runs), heading, None, {"training": [run.training.path for run in
                                                                             pooled.runs], "heldout": None}
    if has_log(args):
        from ..logs.table import LogError
        from ..model.terms import model_named
        from ..studies.ladder import compare_log
        from ..studies.log_fit import fit_logs

        training, heldout = load_logs(args)
        try:
            # The default log fit first: what its robust step and standstill leave out, no model decides.
            logs = fit_logs(training, heldout, model=model_named(log_model(args)), filtering=filter_options(args),
                            sensitivity=False, exclusion=exclusion_options(args))
        except LogError as error:
            raise UserError(str(error)) from None
        low_pass = logs.filter
        comparison = compare_log(logs)
        heading = f"Training log {training.source_text()}; {low_pass_short_note(low_pass, training.effort.name)}"
        return comparison, heading, None, {"training": training.path,
                                           "heldout": None if heldout is None else heldout.path}
    settings = settings_from(with_default_settings(args))
    return compare_experiment(settings), settings_header(settings), settings, None
