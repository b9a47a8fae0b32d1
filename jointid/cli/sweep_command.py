"""`jointid sweep`: the same experiment under K noise seeds, with statistics of every estimate."""

from __future__ import annotations

import argparse
import json

from ..fit import format_number
from ..model import PARAMETER_NAMES
from ..report import per_parameter
from ..sweep import DEFAULT_SEED_COUNT, QUANTITIES, SEED_COUNT_LIMITS, SweepResult, run_sweep
from ..uncertainty import finite_or_none
from .arguments import add_settings_arguments, settings_from, whole_number

NAME = "sweep"

QUANTITY_LABELS = {
    "I": "I (kg m²)",
    "h": "h (kg m)",
    "B": "B (N m s/rad)",
    "training_rmse": "Training RMSE (N m)",
    "heldout_rmse": "Held-out RMSE (N m)",
}
"""Row labels with units."""


def add_parser(subparsers) -> None:
    """Attach the `sweep` subcommand."""
    parser = subparsers.add_parser(
        NAME,
        help="repeat one experiment over many noise seeds and summarise the estimates",
        description="Fit the chosen motion, noise and samples for K seeds starting at --seed "
        "(wrapping past 4294967295 to 0), with one factorisation for all of them; print the mean, "
        "standard deviation and 5/50/95 % percentiles of I, h, B and both RMSEs, the share of "
        "seeds failing a sign check, and the empirical standard deviations beside the expected ones.",
    )
    add_settings_arguments(parser)
    low, high = SEED_COUNT_LIMITS
    parser.add_argument(
        "--seeds",
        type=whole_number(*SEED_COUNT_LIMITS),
        default=DEFAULT_SEED_COUNT,
        metavar="K",
        help=f"number of seeds, {low} to {high:,}; default {DEFAULT_SEED_COUNT}",
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")


def sweep_to_dict(sweep: SweepResult) -> dict:
    """The sweep's statistics as JSON-ready values (None where unavailable)."""
    statistics = {name: None for name in QUANTITIES}
    for name, distribution in sweep.statistics.items():
        statistics[name] = vars(distribution).copy()
    return {
        "seeds": {"first": int(sweep.seeds[0]), "last": int(sweep.seeds[-1]), "count": sweep.seed_count},
        "rank": sweep.rank,
        "condition_number": finite_or_none(sweep.condition_number),
        "statistics": statistics,
        "empirical_std": per_parameter(sweep.empirical_std),
        "expected_std_error": per_parameter(sweep.expected_std_error),
        "sign_failure_fraction": sweep.sign_failure_fraction,
        "sign_failure_fractions": sweep.sign_failure_fractions,
        "message": sweep.message,
    }


def sweep_text(sweep: SweepResult) -> str:
    """A table of the statistics, the standard deviations side by side, and the message."""
    lines = [sweep.message]
    if not sweep.is_full_rank:
        return "\n".join(lines)
    columns = ("mean", "std", "p5", "p50", "p95")
    lines += ["", f"{'':<22}" + "".join(f"{name:>13}" for name in columns)]
    for name in QUANTITIES:
        distribution = vars(sweep.statistics[name])
        cells = ["—" if distribution[c] is None else format_number(distribution[c]) for c in columns]
        lines.append(f"{QUANTITY_LABELS[name]:<22}" + "".join(f"{cell:>13}" for cell in cells))
    if sweep.empirical_std is not None and sweep.expected_std_error is not None:
        pairs = ", ".join(
            f"{name} {format_number(empirical)} vs {format_number(expected)}"
            for name, empirical, expected in zip(PARAMETER_NAMES, sweep.empirical_std, sweep.expected_std_error)
        )
        lines += ["", f"Standard deviation over seeds vs expected from the noise bound: {pairs}."]
    lines.append(f"Seeds failing at least one sign check: {100 * sweep.sign_failure_fraction:.1f} %.")
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    """Run the sweep and print text or JSON; exit status 0."""
    settings = settings_from(args)
    sweep = run_sweep(settings, args.seeds)
    if args.json:
        print(json.dumps({"settings": vars(settings).copy(), **sweep_to_dict(sweep)}, indent=2))
    else:
        print(sweep_text(sweep))
    return 0
