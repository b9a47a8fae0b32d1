"""`jointid fit`: identify a model's parameters for one synthetic experiment (or a log) and report it."""

from __future__ import annotations

import argparse

from ..options import DEFAULT_HORIZON, HORIZON_LIMITS
from .arguments import (
    add_model_argument,
    add_settings_arguments,
    bounded_number,
    settings_from,
)
from .commands import SUBCOMMANDS
from .exit_status import ExitStatus
from .log_arguments import (
    add_log_arguments,
    has_log,
    run_log_fit,
    with_default_settings,
)
from .output import print_json

NAME = "fit"


def add_parser(subparsers) -> None:
    """Attach the `fit` subcommand."""
    parser = subparsers.add_parser(
        NAME,
        help=SUBCOMMANDS[NAME].summary,
        description="Fit I (kg m²), h (kg m) and B (N m s/rad) (and any extra terms of --model) by "
        "column-scaled, pivoted Householder least squares; report the rank, the fit, training RMSE "
        "against the noisy torques and held-out RMSE on 16 noiseless states of a separate motion.",
    )
    add_settings_arguments(parser)
    add_model_argument(parser)
    parser.add_argument("--simulate", action="store_true",
                        help="also integrate the fitted model under the true torque of the validation motion "
                        "(synthetic experiments; needs scipy, about 0.1 s)")
    low, high = HORIZON_LIMITS
    parser.add_argument("--horizon", type=bounded_number(low, high), default=None, metavar="H",
                        help=f"seconds between restarts from the true state in the simulation, {low:g} to {high:g}; "
                        f"default {DEFAULT_HORIZON:g} (implies --simulate)")
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")
    add_log_arguments(parser)


def run(args: argparse.Namespace) -> int:
    """Run the experiment (or fit the --csv log) and print text or JSON; exit status 0."""
    if has_log(args):
        return run_log_fit(args)
    from ..studies.experiment import (
        run_experiment,  # numpy and the numeric modules load only to run
    )

    settings = settings_from(with_default_settings(args))
    result = run_experiment(settings)
    simulate = args.simulate or args.horizon is not None
    horizon = DEFAULT_HORIZON if args.horizon is None else args.horizon
    check = None
    if simulate:
        from ..studies.simulation import simulation_check

        check = simulation_check(result, settings.true_joint, horizon)
    if args.json:  # each output loads only its own presentation modules
        from ..present.documents import fit_document, simulation_object

        extra = simulation_object(check) if simulate else {}
        print_json(fit_document(result, settings=settings, **extra))
    else:
        from ..present.status import simulation_text
        from ..present.summary import fit_summary

        print(fit_summary(result))
        if simulate:
            print()
            print(simulation_text(check))
    return ExitStatus.SUCCESS
