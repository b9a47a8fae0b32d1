"""`jointid design`: the Fourier-series motion that, within the joint's limits, reveals the parameters best."""

from __future__ import annotations

import argparse
import sys

from .. import options  # the design's defaults and limits, as studies.design takes them
from .arguments import (
    UserError,
    bounded_number,
    positive_number,
    setting_type,
    whole_number,
)
from .commands import SUBCOMMANDS
from .exit_status import ExitStatus

NAME = "design"

PROGRESS_SECONDS = 2.0
"""Estimated seconds (jointid.studies.design.design_seconds) from which a design shows its starts on a terminal."""


def criterion_name(text: str) -> str:
    """An argparse type for a design criterion: d, a or cond."""
    name = text.strip().lower()
    if name not in options.CRITERIA:
        raise argparse.ArgumentTypeError(f"must be one of {', '.join(options.CRITERIA)}; got {text!r}")
    return name


def add_parser(subparsers) -> None:
    """Attach the `design` subcommand."""
    parser = subparsers.add_parser(
        NAME,
        help=SUBCOMMANDS[NAME].summary,
        description="Optimise a finite Fourier series q(t) = q_c + sum_k [a_k/(k w) sin(k w t) - b_k/(k w) "
        "cos(k w t)], w = 2 pi/T, for --criterion (d: D-optimal, a: A-optimal, cond: the column-scaled "
        "condition number, shown as the counter-example it is) subject to the limits on a 400-point grid "
        "per period, from --starts random starts; verify the limits on 4000 points; print every parameter's "
        "expected standard error beside rich motion's at the same samples, noise and model, both condition "
        "numbers and the limits' margins. --out writes the motion file that --motion-file reads.",
    )
    envelope = options.RICH_ENVELOPE
    parser.add_argument("--q-max", type=positive_number, default=envelope["q_max"], metavar="RAD",
                        help=f"angle limit |q| (rad), at most pi; default {envelope['q_max']:g} (rich motion's)")
    parser.add_argument("--qd-max", type=positive_number, default=envelope["qd_max"], metavar="RAD/S",
                        help=f"speed limit |qd| (rad/s); default {envelope['qd_max']:g} (rich motion's)")
    parser.add_argument("--qdd-max", type=positive_number, default=envelope["qdd_max"], metavar="RAD/S2",
                        help=f"acceleration limit |qdd| (rad/s²); default {envelope['qdd_max']:g} (rich motion's)")
    parser.add_argument("--tau-max", type=positive_number, default=None, metavar="NM",
                        help="actuator torque limit |tau| of the true joint (N m); default none")
    low, high = options.HARMONIC_LIMITS
    parser.add_argument("--harmonics", type=whole_number(low, high), default=options.DEFAULT_HARMONICS, metavar="K",
                        help=f"harmonics of the series, {low} to {high}; default {options.DEFAULT_HARMONICS}")
    low, high = options.PERIOD_LIMITS
    parser.add_argument("--period", type=bounded_number(low, high), default=options.DEFAULT_PERIOD, metavar="T",
                        help=f"period (s), {low:g} to {high:g}; default {options.DEFAULT_PERIOD:g}")
    parser.add_argument("--samples", type=setting_type("samples"), default=24, metavar="N",
                        help="training samples over 0..8 s the design is for; default 24")
    parser.add_argument("--noise", type=setting_type("noise"), default=options.DEFAULT_NOISE, metavar="X",
                        help="torque noise bound (N m) of the expected standard errors; "
                        f"default {options.DEFAULT_NOISE:.2f}")
    parser.add_argument("--model", type=setting_type("model"), default="plain", metavar="NAME",
                        help="fitted model the design is for (as for fit --model); default plain")
    parser.add_argument("--criterion", type=criterion_name, default=options.DEFAULT_CRITERION, metavar="{d,a,cond}",
                        help="d: maximise log det of the information matrix (relative units); a: minimise the sum "
                        "of relative variances; cond: minimise the column-scaled condition number; "
                        f"default {options.DEFAULT_CRITERION}")
    low, high = options.STARTS_LIMITS
    parser.add_argument("--starts", type=whole_number(low, high), default=options.DEFAULT_STARTS, metavar="S",
                        help=f"random starts of the optimiser, {low} to {high}; default {options.DEFAULT_STARTS}")
    parser.add_argument("--seed", type=whole_number(0, 2**32 - 1), default=options.DEFAULT_SEED, metavar="SEED",
                        help="seed of the random starts (the same seed gives the same design); "
                        f"default {options.DEFAULT_SEED}")
    parser.add_argument("--out", metavar="FILE", help="write the designed motion to this JSON motion file")
    parser.add_argument("--force", action="store_true", help="replace FILE if it exists (only a regular file: never a symlink, a FIFO, a device or a folder)")
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")


def run(args: argparse.Namespace) -> int:
    """Design the motion, print text or JSON, and write --out; exit status 0."""
    from ..files import ExportError
    from ..present.design import design_document, design_text
    from ..studies.design import (
        DesignError,
        DesignSpec,
        Limits,
        design_motion,
        design_seconds,
        over_budget,
    )
    from ..synthetic.fourier import save_motion
    from ..synthetic.settings import Settings
    from .output import print_json

    try:
        spec = DesignSpec(
            limits=Limits(args.q_max, args.qd_max, args.qdd_max, args.tau_max),
            criterion=args.criterion, harmonics=args.harmonics, period=args.period, starts=args.starts,
            seed=args.seed, experiment=Settings(noise=args.noise, samples=args.samples, model=args.model),
        )
    except DesignError as error:
        raise UserError(str(error)) from None
    # --force only replaces files: a design over budget is refused outright, since lowering a flag always helps.
    problem = over_budget(spec)
    if problem is not None:
        raise UserError(problem)
    show = sys.stderr.isatty() and design_seconds(spec) >= PROGRESS_SECONDS
    try:
        result = design_motion(spec, progress=progress_line if show else None)
    except DesignError as error:
        raise UserError(str(error)) from None
    finally:
        if show:  # clear the progress line, also after Ctrl+C
            print("\r\033[K", end="", file=sys.stderr, flush=True)
    if args.out is not None:
        try:
            save_motion(result.motion, args.out, overwrite=args.force)
        except ExportError as error:
            hint = " (add --force to replace it)" if "already exists" in str(error) else ""
            raise UserError(f"{error}{hint}") from None
    if args.json:
        print_json(design_document(result))
    else:
        print(design_text(result))
        if args.out is not None:
            from ..text_safety import shown_name

            print(f"\nWrote {shown_name(args.out)}: train on it with --motion-file {shown_name(args.out)}.")
    return ExitStatus.SUCCESS


def progress_line(done: int, total: int) -> None:
    """Rewrite one line on stderr: 'jointid design: start 3 of 8 done'."""
    print(f"\rjointid design: start {done:,} of {total:,} done", end="", file=sys.stderr, flush=True)
