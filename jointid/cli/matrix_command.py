"""`jointid matrix`: the cross-excitation table of prediction errors."""

from __future__ import annotations

import argparse
import json

from ..cross_excitation import CrossExcitationTable, cross_excitation
from ..fit import format_number
from ..model import PARAMETER_NAMES
from ..motions import VALIDATION_SAMPLES
from .arguments import add_settings_arguments, settings_from

NAME = "matrix"

TRAINING_MARK = "*"
"""Marks an entry predicted on the motion its fit was trained on."""


def add_parser(subparsers) -> None:
    """Attach the `matrix` subcommand."""
    parser = subparsers.add_parser(
        NAME,
        help="fit each training motion and predict every motion: a table of torque RMSE",
        description="Fit rich, slow and holds at the given noise, samples and seed (--motion is "
        "ignored: every motion gets a row) and predict the noiseless torque of the rich and slow "
        "motions (at the same sample count) and of the 16 validation states. An entry on a row's "
        "own motion is training data, not a held-out test.",
    )
    add_settings_arguments(parser)
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")


def matrix_to_dict(table: CrossExcitationTable) -> dict:
    """The table as JSON-ready values: one object per row, cells keyed by prediction motion."""
    rows = []
    for row in table.rows:
        estimate = row.fit.estimate
        rows.append(
            {
                "training_motion": row.training_motion,
                "rank": row.fit.rank,
                "estimate": None if estimate is None else dict(zip(PARAMETER_NAMES, map(float, estimate))),
                "cells": {
                    cell.prediction_motion: {"rmse": cell.rmse, "training_data": cell.is_training_data}
                    for cell in row.cells
                },
            }
        )
    return {"prediction_motions": list(table.prediction_motions), "rows": rows}


def matrix_text(table: CrossExcitationTable) -> str:
    """The table with rows per training motion, its legend and sample counts."""
    settings = table.settings
    width = 18
    headers = [("test (validation)" if m == "test" else m) for m in table.prediction_motions]
    lines = [
        f"Torque prediction RMSE (N m) against noiseless truth; noise {format_number(settings.noise, 2)} N m, "
        f"{settings.samples} samples, seed {settings.seed}",
        f"{'fitted on':<16}" + "".join(f"{h:>{width + 1}}" for h in headers),
    ]
    for row in table.rows:
        cells = [
            "unavailable" if c.rmse is None else format_number(c.rmse) + (TRAINING_MARK if c.is_training_data else " ")
            for c in row.cells
        ]
        label = f"{row.training_motion} (rank {row.fit.rank})"
        lines.append(f"{label:<16}" + "".join(f"{cell:>{width + 1}}" for cell in cells))
    lines += [
        f"{TRAINING_MARK} training data: the fit saw these states (with noisy torques); not a held-out test.",
        f"rich and slow columns: {settings.samples} samples at the training instants; "
        f"test: the {VALIDATION_SAMPLES} validation states. holds has no unique fit.",
    ]
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    """Build the table and print text or JSON; exit status 0."""
    settings = settings_from(args)
    table = cross_excitation(settings)
    if args.json:
        document = {"settings": vars(settings).copy(), **matrix_to_dict(table)}
        print(json.dumps(document, indent=2))
    else:
        print(matrix_text(table))
    return 0
