"""`jointid report`: the fit `jointid fit` makes, written as one self-contained HTML page (and optionally Markdown)."""

from __future__ import annotations

import argparse
import os
import sys

from ..options import DEFAULT_HORIZON, HORIZON_LIMITS
from .arguments import (
    UserError,
    add_model_argument,
    add_settings_arguments,
    bounded_number,
    settings_from,
)
from .commands import SUBCOMMANDS
from .exit_status import ExitStatus
from .log_arguments import (
    add_log_arguments,
    fit_any_logs,
    has_log,
    with_default_settings,
)

NAME = "report"


def add_parser(subparsers) -> None:
    """Attach the `report` subcommand: `fit`'s inputs, plus where to write and whether to add the ladder."""
    parser = subparsers.add_parser(
        NAME,
        help=SUBCOMMANDS[NAME].summary,
        description="Fit as `jointid fit` does (a synthetic experiment, a --csv log, several runs or a --bag joint) "
        "and write one HTML file that needs no network to view: the settings or the logs with their notes, "
        "the parameter table with standard errors, intervals and verdicts, the training and held-out torque "
        "charts, the residual views, what was left out, the checks, and the status sentence. Charts need "
        "pip install 'jointid[report]' (matplotlib).",
    )
    add_settings_arguments(parser)
    add_model_argument(parser)
    parser.add_argument("--out", metavar="REPORT.html", required=True, help="the HTML file to write")
    parser.add_argument("--markdown", metavar="REPORT.md",
                        help="also write the report as Markdown, each chart an SVG file beside it "
                        "(REPORT-training.svg, ...)")
    parser.add_argument("--force", action="store_true",
                        help="replace the report's files if they exist (only regular files: never a symlink, a "
                        "FIFO, a device or a folder)")
    parser.add_argument("--compare", action="store_true",
                        help="add the model ladder (what `jointid compare` prints for the same data)")
    parser.add_argument("--simulate", action="store_true",
                        help="add the simulation check of a synthetic experiment (as `jointid fit --simulate`)")
    low, high = HORIZON_LIMITS
    parser.add_argument("--horizon", type=bounded_number(low, high), default=None, metavar="H",
                        help=f"seconds between restarts in the simulation, {low:g} to {high:g}; default "
                        f"{DEFAULT_HORIZON:g} (implies --simulate)")
    add_log_arguments(parser)


def run(args: argparse.Namespace) -> int:
    """Fit, build the report, write it (HTML, and Markdown with its charts) as one group; print where."""
    from ..files import ExportError, write_texts
    from ..present.report_charts import ReportExtraMissing
    from ..text_safety import shown_name

    check_destinations(report_paths(args), args.force)
    check_drawing_library()
    from ..present.chart_process import ChartProcess

    # A child imports matplotlib on another core while the data are read and fitted: worth it for long fits only.
    charts = ChartProcess() if long_fit(args) else None
    try:
        texts = report_texts(args, command_line(getattr(args, "argv", sys.argv[1:])), charts)
    except ReportExtraMissing as error:
        raise UserError(str(error)) from None
    finally:
        if charts is not None:
            charts.close()
    try:
        write_texts(texts, overwrite=args.force)
    except ExportError as error:
        hint = " (add --force to replace it)" if "already exists" in str(error) else ""
        raise UserError(f"{error}{hint}") from None
    chart_files = len(texts) - 2
    charts = f"{chart_files} chart{'s' if chart_files != 1 else ''} beside it"
    written = shown_name(args.out) if args.markdown is None else \
        f"{shown_name(args.out)}, {shown_name(args.markdown)} and {charts}"
    print(f"Wrote {written}.")
    return ExitStatus.SUCCESS


def check_destinations(paths: list[str], force: bool) -> None:
    """UserError (one line) for a path that is taken (without `force`), special, or in a missing folder: found
    before the fit, which may take a minute. (The chart files beside a Markdown report are checked as they are
    written.)"""
    from ..files import ExportError, refuse_special_destination, shown_path

    for path in paths:
        try:
            refuse_special_destination(path)
        except ExportError as error:
            raise UserError(str(error)) from None
        if not force and os.path.lexists(path):
            raise UserError(f"{shown_path(path)}: already exists; not overwriting it (add --force to replace it)")
        if not os.path.isdir(os.path.dirname(path) or os.curdir):
            raise UserError(f"{shown_path(path)}: cannot write: No such folder")


def check_drawing_library() -> None:
    """One line naming the extra when matplotlib is not installed, before any fit is made.

    (Importing it in a background thread during the fit was tried before the child process: on a busy machine
    the thread and the fit fought over Python's lock and the report took longer, bench_report.)
    """
    import importlib.util

    from ..present.report_charts import EXTRA_HINT

    if importlib.util.find_spec("matplotlib") is None:
        raise UserError(EXTRA_HINT)


LONG_FIT_BYTES = 10_000_000
"""Logs of at least this many bytes (about 100,000 rows of text) take longer to read and fit than matplotlib takes
to import (a quarter of a second), so their charts are drawn by a child process started first; a smaller fit
would only wait for the child (and a test suite would wait for it on every report)."""
LONG_FIT_SAMPLES = 1_000_000
"""Synthetic experiments of at least this many samples take as long (their fit and the held-out check)."""


def long_fit(args: argparse.Namespace) -> bool:
    """Whether the data take longer to read and fit than matplotlib to import: big log files, or a synthetic
    experiment of a million samples or more."""
    if not has_log(args):
        return (args.samples or 0) >= LONG_FIT_SAMPLES
    paths = ([args.bag] if args.bag is not None else [args.wpilog] if getattr(args, "wpilog", None) is not None
             else list(getattr(args, "runs", None) or [args.csv]))
    if args.heldout is not None:
        paths.append(args.heldout)
    total = 0
    for path in paths:
        try:
            if os.path.isdir(path):  # a ROS 2 bag is a folder
                total += sum(entry.stat().st_size for entry in os.scandir(path) if entry.is_file())
            else:
                total += os.stat(path).st_size
        except OSError:
            pass  # the reading will say what is wrong with it
    return total >= LONG_FIT_BYTES


def report_paths(args: argparse.Namespace) -> list[str]:
    """The HTML path and the Markdown path (if asked); UserError when they are the same file."""
    paths = [args.out] + ([] if args.markdown is None else [args.markdown])
    if len(paths) == 2 and os.path.abspath(paths[0]) == os.path.abspath(paths[1]):
        raise UserError(f"--out and --markdown: both name {args.out}; give two files")
    return paths


def command_line(argv: list[str]) -> str:
    """The command as typed, for the report's footer: 'jointid report --motion slow ...' (a word holding a character
    that is not printable escaped as every name is, by shown_name)."""
    from ..files import shown_command

    return shown_command(["jointid", *argv])


def report_texts(args: argparse.Namespace, command: str, charts=None) -> dict[str, str]:
    """{path: text} of every file the report writes (the HTML, and the Markdown with its charts); the charts are
    drawn by `charts` (a chart_process.ChartProcess) when given."""
    from ..present.report import draw
    from ..present.report_writers import html_page, made_by, markdown_files

    report = draw(build_report(args), charts)
    footer = made_by(command)
    texts = {args.out: html_page(report, footer)}
    if args.markdown is not None:
        texts.update(markdown_files(report, args.markdown, footer))
    return texts


def build_report(args: argparse.Namespace):
    """The report (present.report.Report) of what `jointid fit` would fit for these arguments."""
    from ..present import report

    comparison = heading = None
    if has_log(args):
        from .effort_arguments import effort_extras

        fitted = fit_any_logs(args)  # several runs (repeated --csv, a SysId log's tests) or one log
        if args.compare:
            from .compare_command import compare

            comparison, heading, _, _ = compare(args, fitted)
        extras = tuple(effort_extras(args, fitted)[0])
        if hasattr(fitted, "runs"):
            return report.runs_report(fitted, comparison=comparison, comparison_heading=heading, extras=extras)
        return report.logs_report(fitted, comparison=comparison, comparison_heading=heading, extras=extras)
    from ..studies.experiment import run_experiment

    if args.compare:
        from .compare_command import compare

        comparison, heading, _, _ = compare(args)
    settings = settings_from(with_default_settings(args))
    result = run_experiment(settings)
    simulate = args.simulate or args.horizon is not None
    check = None
    if simulate:
        from ..studies.simulation import simulation_check

        check = simulation_check(result, settings.true_joint, DEFAULT_HORIZON if args.horizon is None else args.horizon)
    return report.synthetic_report(result, settings, comparison=comparison, simulation=check, simulated=simulate)
