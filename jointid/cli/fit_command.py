"""`jointid fit`: identify I, h, B for one synthetic experiment and report it."""

from __future__ import annotations

import argparse
import json

from ..experiment import run_experiment
from ..fit import format_number
from ..motions import TRAINING_MOTIONS
from ..report import fit_document, readouts_text, uncertainty_text
from .arguments import add_settings_arguments, settings_from
from .log_fit import add_log_arguments, run_log_fit, with_default_settings

NAME = "fit"


def add_parser(subparsers) -> None:
    """Attach the `fit` subcommand."""
    parser = subparsers.add_parser(
        NAME,
        help="fit I, h, B to one experiment and print every readout",
        description="Fit I (kg m²), h (kg m) and B (N m s/rad) by column-scaled, pivoted "
        "Householder least squares; report the rank, the fit, training RMSE against the noisy "
        "torques and held-out RMSE on 16 noiseless states of a separate motion.",
    )
    add_settings_arguments(parser)
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")
    add_log_arguments(parser)


def run(args: argparse.Namespace) -> int:
    """Run the experiment (or fit the --csv log) and print text or JSON; exit status 0."""
    if args.csv is not None:
        return run_log_fit(args)
    settings = settings_from(with_default_settings(args))
    result = run_experiment(settings)
    if args.json:
        document = fit_document(result, settings=vars(settings).copy())
        print(json.dumps(document, indent=2))
    else:
        motion = TRAINING_MOTIONS[settings.motion].label
        print(
            f"{motion}, torque noise bound {format_number(settings.noise, 2)} N m, "
            f"{settings.samples} samples, seed {settings.seed}"
        )
        print(readouts_text(result))
        print()
        print(uncertainty_text(result))
    return 0
