"""What `jointid report` says, as a list of blocks (headings, paragraphs, tables, charts) for the writers.

Every sentence and table comes from the presentation layer's own texts (the
readouts, the uncertainty text, the status sentence, a log's notes, checks and
what was left out, the runs' table, the ladder), so a report says exactly what
`jointid fit` prints and the explorer shows; this module only arranges them.
The writers (`jointid.present.report_writers`) turn the blocks into HTML or
Markdown; the charts are drawn by `jointid.present.report_charts`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from .text import format_number

if TYPE_CHECKING:
    from ..estimation.fit import FitResult
    from ..studies.ladder import Comparison
    from ..studies.log_fit import LoadedLogs
    from ..studies.runs import PooledRuns
    from ..synthetic.settings import Settings


@dataclass(frozen=True)
class Heading:
    """A section heading; `anchor` is its id in the page."""

    text: str
    level: int = 2
    anchor: str = ""


@dataclass(frozen=True)
class Paragraph:
    """Running text, one paragraph."""

    text: str


@dataclass(frozen=True)
class Preformatted:
    """Text whose lines and spacing matter (aligned text tables, the command line's uncertainty lines)."""

    text: str


@dataclass(frozen=True)
class Table:
    """A table of text cells; the first column is a label, the others are right-aligned numbers or words."""

    header: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]
    caption: str = ""


@dataclass(frozen=True)
class Chart:
    """A chart: `name` is unique within a report (ids, file names), `title` what it shows, `caption` its summary
    in words, `drawing` the report_charts function and arguments that draw it, `svg` the drawing once made
    (`draw`)."""

    name: str
    title: str
    caption: str
    drawing: tuple[str, tuple]
    svg: str = ""


Block = Heading | Paragraph | Preformatted | Table | Chart


@dataclass(frozen=True)
class Report:
    """A whole report: its title, a one-line subject, and its blocks in order."""

    title: str
    subject: str
    blocks: tuple[Block, ...]


# One fit's sections -------------------------------------------------------------------------------------------


def parameter_table(result: FitResult) -> Table:
    """Each parameter's value, standard error, relative error, 95 % interval and verdict, as the uncertainty text
    gives them (the fit's judgement: after every check, with why it is weaker than the noise's)."""
    from ..estimation.uncertainty import AT_BOUND
    from .readouts import closing_lines, parameter_notes

    model, uncertainty, estimate = result.model, result.uncertainty, result.estimate
    notes = parameter_notes(result)
    judgement = result.judgement
    header = ("Parameter", "Value", "Standard error", "Relative", "95 % interval (Student t)", "Verdict",
              "Sign rule")
    rows = []
    for index, (parameter, note) in enumerate(zip(model.parameters, notes)):
        value = "unavailable" if estimate is None else format_number(estimate[index])
        fails = f"fails {parameter.requirement}" if parameter.name in result.sign_failures else ""
        if uncertainty is None or uncertainty.verdict_std_error is None:
            rows.append((parameter.symbol_with_unit, value, "", "", "", note.text, fails))
            continue
        if uncertainty.verdicts[index] == AT_BOUND:
            rows.append((parameter.symbol_with_unit, value, "", "", "", AT_BOUND, fails))
            continue
        interval = "" if uncertainty.interval95 is None else \
            f"[{format_number(uncertainty.interval95[index][0])}, {format_number(uncertainty.interval95[index][1])}]"
        rows.append((parameter.symbol_with_unit, value, note.text, f"{uncertainty.relative_std_pct[index]:.1f} %",
                     interval, _with_reason(judgement.verdicts[index], judgement.reasons[index]), fails))
    # Where the ± comes from, as the explorer says it under its readouts.
    caption = " ".join(text for label, text in closing_lines(result) if text.startswith("±"))
    return Table(header, tuple(rows), caption)


def _with_reason(verdict: str, reason: str) -> str:
    """'weak (moved by the derivative settings)', or the verdict alone when no check weakened it."""
    return f"{verdict} ({reason})" if reason else verdict


def readout_table(result: FitResult, linear: bool = False) -> Table:
    """The lab's readouts: rank, each parameter, both RMSEs, the motion's RMS (per metre when `linear`)."""
    from .readouts import readouts

    return Table(("Readout", "Value"), tuple(
        (item.label, item.text + (f"  fails {item.failed_requirement}" if item.sign_failure else ""))
        for item in readouts(result, linear)))


def fit_blocks(result: FitResult, prefix: str, training_chart=None, training_count: int | None = None,
               heldout_title: str | None = None, linear: bool = False) -> list[Block]:
    """The parameter table, the readouts, the uncertainty in words, the torque charts and the residual views of
    one fit. `prefix` makes the charts' names unique; `training_chart` is a log's chart (left-out samples faint)
    of `training_count` samples before thinning."""
    from .charts import heldout_chart
    from .charts import training_chart as synthetic_training_chart
    from .readouts import uncertainty_text
    from .report_charts import MAX_POINTS, thinned_note

    blocks: list[Block] = [
        Heading("Parameters", 3, f"{prefix}parameters"),
        parameter_table(result),
        Heading("Readouts", 3, f"{prefix}readouts"),
        readout_table(result, linear),
        Preformatted(uncertainty_text(result)),
        Heading(f"Training and held-out {result.model.effort.name}s", 3, f"{prefix}torques"),  # or voltages
    ]
    training = training_chart or synthetic_training_chart(result, columns=MAX_POINTS)
    count = result.training.count if training_count is None else training_count
    blocks.append(Chart(f"{prefix}training", training.titles[0], training.summaries[0],
                        ("torque_svg", (training, f"{prefix}training", thinned_note(count)))))
    heldout = heldout_chart(result, log_name=heldout_title, columns=MAX_POINTS)
    if heldout is None:
        from .status import NO_HELDOUT

        blocks.append(Paragraph(NO_HELDOUT))
    else:
        blocks.append(Chart(f"{prefix}heldout", heldout.titles[0], heldout.summaries[0],
                            ("torque_svg", (heldout, f"{prefix}heldout", thinned_note(result.heldout.count)))))
    blocks += residual_blocks(result, prefix)
    return blocks


def residual_blocks(result: FitResult, prefix: str) -> list[Block]:
    """The residual views: the training residuals against time, angle, velocity and acceleration, and what
    structure against each would mean."""
    from ..estimation.residuals import AXES, AXIS_LABELS, residual_data
    from .charts import residual_scatter, residual_summary
    from .report_charts import thin_scatter, thinned_note
    from .text import capitalise

    data = residual_data(result)
    unit = result.model.effort.unit
    scatters = [thin_scatter(residual_scatter(data, axis)) for axis in AXES]
    return [Heading("Residuals", 3, f"{prefix}residuals"),
            Chart(f"{prefix}residuals", f"Training residuals ({unit}) against time, angle, velocity and acceleration",
                  residual_summary(data),
                  ("residuals_svg", (scatters, f"{prefix}residuals", thinned_note(len(data.residuals)), unit))),
            Table(("Against", "What structure there would mean"),
                  tuple((capitalise(AXIS_LABELS[axis]), data.note(axis)) for axis in AXES))]


def draw(report: Report, process=None) -> Report:
    """The report with every chart drawn (by a chart_process.ChartProcess when given, else here)."""
    import dataclasses

    from .chart_process import draw_charts

    charts = [block for block in report.blocks if isinstance(block, Chart)]
    drawn = iter(draw_charts([chart.drawing for chart in charts], process))
    blocks = tuple(dataclasses.replace(block, svg=next(drawn)) if isinstance(block, Chart) else block
                   for block in report.blocks)
    return dataclasses.replace(report, blocks=blocks)


# Reports by source ---------------------------------------------------------------------------------------------


def synthetic_report(result: FitResult, settings: Settings, *, comparison: Comparison | None = None,
                     simulation=None, simulated: bool = False) -> Report:
    """A synthetic experiment's report: the settings, the status, the fit, and the ladder or simulation if asked."""
    from .documents import settings_object
    from .status import simulation_text, status_message
    from .text import settings_header

    header = settings_header(settings)
    values = settings_object(settings)
    blocks: list[Block] = [
        Heading("Status", 2, "status"), Paragraph(status_message(result)),
        Heading("Settings", 2, "settings"), Paragraph(header),
        Table(("Setting", "Value"), tuple((name, _setting_text(value)) for name, value in values.items()
                                         if not isinstance(value, dict))),
        Heading("Fit", 2, "fit"),
        *fit_blocks(result, ""),
    ]
    if simulated:
        blocks += [Heading("Simulation", 2, "simulation"), Preformatted(simulation_text(simulation))]
    if comparison is not None:
        blocks += ladder_blocks(comparison, header)
    return Report("jointid report", header, tuple(blocks))


def _setting_text(value) -> str:
    """A setting's value as text: numbers as given, words as they are."""
    return f"{value:g}" if isinstance(value, float) else str(value)


def log_blocks(logs: LoadedLogs, prefix: str = "") -> list[Block]:
    """A fit of logs: what was read, the status, the checks (sensitivity, terms the model lacks), what was left
    out with its intervals, the fit and its charts, then every note."""
    from .charts import log_training_chart
    from .notes import log_notes
    from .report_charts import MAX_POINTS
    from .status import status_message
    from .summary import log_checks

    found, left = log_checks(logs)
    blocks: list[Block] = [
        Heading("Status", 2, f"{prefix}status"), Paragraph(status_message(logs.result)),
        Heading("Logs", 2, f"{prefix}logs"), *(Paragraph(line) for line in logs.source_lines()),
        Heading("Checks", 2, f"{prefix}checks"),
        *(Paragraph(text) for text in found),
    ]
    if logs.sensitivity is None:
        blocks.append(Paragraph("No sensitivity check was run."))
    blocks += [Heading("Left out of the fit", 2, f"{prefix}excluded"),
               Paragraph(left if left is not None else "Every sample kept: nothing was left out.")]
    intervals = excluded_table(logs)
    if intervals is not None:
        blocks.append(intervals)
    blocks += [Heading("Fit", 2, f"{prefix}fit"),
               *fit_blocks(logs.result, prefix, log_training_chart(logs, columns=MAX_POINTS),
                           _filtered_count(logs), logs.heldout_name, logs.training.position_unit == "metres")]
    notes = log_notes(logs)
    if notes:
        blocks += [Heading("Notes", 2, f"{prefix}notes"), *(Paragraph(note) for note in notes)]
    return blocks


def _filtered_count(logs: LoadedLogs) -> int:
    """How many samples a log's training chart is drawn from: every filtered sample when some were left out (they
    are drawn faint), else the fitted ones."""
    left = logs.exclusions
    if left is None or left.regressor is None or bool(left.kept.all()):
        return logs.result.training.count
    return len(left.torque)


def excluded_table(logs: LoadedLogs) -> Table | None:
    """Each stretch the fit left out (seconds from the log's start) and why; None when none was."""
    left = logs.exclusions
    if left is None or not left.excluded:
        return None
    inside = set(left.within)
    rows = tuple((f"{start:.2f}", f"{end:.2f}", f"{end - start:.2f}",
                  "outside torque" if (start, end) in inside else "the log's end: the model stops matching")
                 for start, end in left.excluded)
    return Table(("From (s)", "To (s)", "Length (s)", "Why"), rows,
                 "Seconds from the log's start; standstill is left out besides, sample by sample.")


def extra_blocks(extras: tuple[str, ...]) -> list[Block]:
    """The motor's physical parameters and the controller's gains (`--motor`, `--gains wpilib`), as `jointid fit`
    prints them: tables and code lines kept whole."""
    if not extras:
        return []
    return [Heading("Motor and gains", 2, "gains"), *(Preformatted(text) for text in extras)]


def logs_report(logs: LoadedLogs, *, comparison: Comparison | None = None, comparison_heading: str = "",
                extras: tuple[str, ...] = ()) -> Report:
    """A fit of logs' report (`jointid report --csv LOG`); `extras` are the motor's and the gains' texts."""
    blocks = log_blocks(logs) + extra_blocks(extras)
    if comparison is not None:
        blocks += ladder_blocks(comparison, comparison_heading)
    return Report("jointid report", logs.source_lines()[0], tuple(blocks))


def runs_report(pooled: PooledRuns, *, comparison: Comparison | None = None, comparison_heading: str = "",
                extras: tuple[str, ...] = ()) -> Report:
    """Several runs of one joint: the per-run table with the pooled fit (and the pooled fit's motor and gains),
    then each run's own report."""
    from .runs import runs_parts

    heading, table, *sentences = runs_parts(pooled)
    blocks: list[Block] = [Heading("Runs", 2, "runs"), Paragraph(heading), Preformatted(table),
                           *(Paragraph(sentence) for sentence in sentences), *extra_blocks(extras)]
    if comparison is not None:
        blocks += ladder_blocks(comparison, comparison_heading)
    for number, run in enumerate(pooled.runs, start=1):
        blocks.append(Heading(f"Run {number}: {run.name}", 1, f"run{number}"))
        blocks += log_blocks(run, f"run{number}-")
    return Report("jointid report", heading.rstrip(":"), tuple(blocks))


def ladder_blocks(comparison: Comparison, heading: str) -> list[Block]:
    """The model ladder: one row per model, BIC's choice and what the others show (`jointid compare`)."""
    from .comparison import comparison_sentences, comparison_table

    return [Heading("Model ladder", 2, "ladder"), Paragraph(heading), Preformatted(comparison_table(comparison)),
            Paragraph(" ".join(comparison_sentences(comparison)))]
