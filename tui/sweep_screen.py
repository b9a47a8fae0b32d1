"""The seed-sweep view: the current experiment under K noise seeds, as histograms and a table."""

from __future__ import annotations

from pathlib import Path

import math
from dataclasses import dataclass

from textual import work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal
from textual.screen import Screen
from textual.widgets import Label, ProgressBar, Static
from textual.worker import Worker, WorkerState, get_current_worker

from jointid.fit import format_number
from jointid.model import PARAMETER_NAMES, PARAMETER_UNITS, SIGN_REQUIREMENTS, TRUE_PARAMETERS
from jointid.motions import TRAINING_MOTIONS
from jointid.settings import Settings, SettingsError
from jointid.sweep import DEFAULT_SEED_COUNT, SweepCancelled, SweepResult, run_sweep

from .footer import KeyFooter
from .small_plots import HistogramData, SmallPlot
from .stepper import StepRange, Stepper
from .tables import text_table

SEED_COUNT_LIMITS = (1, 100_000)
"""Seeds the view accepts: a 100,000-seed sweep still finishes in about a second."""
PROGRESS_STEPS = 50
"""Chunks a sweep is split into, so the progress bar moves even though each chunk is fast."""
MIN_CHUNK = 500
"""Smallest chunk: below it the per-chunk overhead outweighs the work."""


@dataclass(frozen=True)
class SeedCountRange(StepRange):
    """The seed-count control's range; the count is not an experiment setting, so it parses itself."""

    def parse(self, text: str) -> float:
        """Typed text as a whole number of seeds in range, or raise SettingsError."""
        text = text.strip()
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or not self.low <= value <= self.high:
            raise SettingsError(self.field, f"seeds must be a whole number {self.describe()}; got {text!r}")
        return value


SEED_COUNT_RANGE = SeedCountRange("seeds", *SEED_COUNT_LIMITS, 100, 1000)
"""K: Left/Right step 100 seeds, Shift 1000; typed values from 1 to 100,000."""

ROW_LABELS = ("true value", "mean", "std (empirical)", "std (expected)", "p5", "p50 (median)", "p95",
              "sign check fails")
"""Rows of the statistics table, one column per parameter and RMSE."""


def settings_line(settings: Settings) -> str:
    """The experiment a view is about, e.g. 'Slow motion, noise 0.20 N m, 24 samples, seed 7'."""
    return (f"{TRAINING_MOTIONS[settings.motion].label}, noise {settings.noise:.2f} N m, "
            f"{settings.samples} samples, seed {settings.seed}")


def chunk_size(seed_count: int) -> int:
    """Seeds per chunk for a sweep of seed_count, so progress arrives about PROGRESS_STEPS times."""
    return max(MIN_CHUNK, math.ceil(seed_count / PROGRESS_STEPS))


def statistics_rows(result: SweepResult) -> list[list[str]]:
    """The statistics table's rows for a full-rank sweep: one column per I, h, B, both RMSEs."""
    stats = result.statistics
    names = (*PARAMETER_NAMES, "training_rmse", "heldout_rmse")
    expected = dict(zip(PARAMETER_NAMES, result.expected_std_error if result.expected_std_error is not None
                        else (None,) * 3))
    fractions = result.sign_failure_fractions

    def cell(value) -> str:
        return "-" if value is None else format_number(value)

    rows = [
        [cell(TRUE_PARAMETERS[i]) for i in range(3)] + ["", ""],
        [cell(stats[name].mean) for name in names],
        [cell(stats[name].std) for name in names],
        [cell(expected[name]) for name in PARAMETER_NAMES] + ["", ""],
        [cell(stats[name].p5) for name in names],
        [cell(stats[name].p50) for name in names],
        [cell(stats[name].p95) for name in names],
        [f"{100 * fractions[name]:.1f} %" for name in PARAMETER_NAMES] + ["", ""],
    ]
    return [[label, *row] for label, row in zip(ROW_LABELS, rows)]


def statistics_table(result: SweepResult) -> str:
    """The statistics table as aligned text, or why there is none."""
    if not result.is_full_rank:
        return ""
    header = ["statistic", *PARAMETER_NAMES, "train RMSE", "held RMSE"]
    return text_table(header, statistics_rows(result))


def sign_failure_line(result: SweepResult) -> str:
    """How often any sign check fails, naming the requirements."""
    if result.sign_failure_fraction is None:
        return ""
    checks = ", ".join(SIGN_REQUIREMENTS[name] for name in PARAMETER_NAMES)
    return f"Seeds failing a sign check ({checks}): {100 * result.sign_failure_fraction:.1f} %."


def histograms(result: SweepResult) -> list[HistogramData]:
    """One histogram per parameter with the true value marked."""
    return [
        HistogramData(
            titles=(
                f"{name} ({PARAMETER_UNITS[name]}), {result.seed_count} seeds; true {TRUE_PARAMETERS[i]:g} at │",
                f"{name} ({PARAMETER_UNITS[name]}); true {TRUE_PARAMETERS[i]:g} at │",
                f"{name}; true {TRUE_PARAMETERS[i]:g} at │",
            ),
            values=result.values(name),
            true_value=float(TRUE_PARAMETERS[i]),
        )
        for i, name in enumerate(PARAMETER_NAMES)
    ]


class SweepScreen(Screen):
    """Seed sweep of the current experiment, run in a worker thread with progress and cancel."""

    CSS_PATH = Path(__file__).with_name("views.tcss")  # read when first opened, not at start-up

    BINDINGS = [
        # Priority: the seed-count field has focus and would otherwise take Escape.
        Binding("escape", "back", "Cancel / back", priority=True,
                tooltip="Cancel a running sweep, otherwise return to the explorer"),
        # Priority too, or the focused seed-count field would type the letters.
        Binding("c", "cancel", "Cancel", priority=True, tooltip="Stop a running sweep"),
        Binding("g", "run", "Run again", priority=True,
                tooltip="Run the sweep again with the current seed count"),
    ]

    def __init__(self, settings: Settings, seed_count: int = DEFAULT_SEED_COUNT) -> None:
        """Create the view.

        Args:
            settings: The experiment to sweep; its seed is the first seed.
            seed_count: K, the number of seeds to start with.
        """
        super().__init__()
        self.settings = settings
        self.seed_count = int(SEED_COUNT_RANGE.clamp(seed_count))
        self.result: SweepResult | None = None

    def compose(self) -> ComposeResult:
        """Settings line, seed-count field and progress, histograms, table, summary, footer."""
        yield Static(f"Seed sweep: {settings_line(self.settings)} onward", id="sweep-title", markup=False)
        with Horizontal(id="sweep-controls"):
            yield Label("Seeds (K)", id="sweep-count-label")
            yield Stepper(SEED_COUNT_RANGE, self.seed_count, id="sweep-count")
            yield ProgressBar(total=self.seed_count, show_eta=False, id="sweep-progress")
            yield Static("", id="sweep-state", markup=False)
        with Horizontal(id="sweep-histograms"):
            for name in PARAMETER_NAMES:
                yield SmallPlot(id=f"histogram-{name}", classes="histogram")
        yield Static("", id="sweep-table", markup=False)
        yield Static("", id="sweep-summary", markup=False)
        yield KeyFooter()

    def on_mount(self) -> None:
        """Start the first sweep with the seed-count field focused."""
        self.query_one(Stepper).focus()
        self.action_run()

    def on_stepper_committed(self, message: Stepper.Committed) -> None:
        """A new seed count: sweep again (an exclusive worker drops the one still running)."""
        message.stop()
        self.seed_count = int(message.value)
        message.stepper.show_value(self.seed_count)  # the stepper shows what its owner holds
        self.action_run()

    def action_run(self) -> None:
        """Run the sweep for the current seed count."""
        progress = self.query_one(ProgressBar)
        progress.update(total=self.seed_count, progress=0)
        self.query_one("#sweep-state", Static).update(f"running {self.seed_count} seeds…")
        self.sweep(self.seed_count)

    @work(thread=True, exclusive=True, group="sweep")
    def sweep(self, seed_count: int) -> SweepResult | None:
        """Fit every seed in a thread, reporting progress; returns None when cancelled."""
        worker = get_current_worker()

        def progress(done: int, total: int) -> None:
            if not worker.is_cancelled:
                self.app.call_from_thread(self._progress, done, total)

        try:
            result = run_sweep(self.settings, seed_count, chunk_size=chunk_size(seed_count),
                               progress=progress, cancelled=lambda: worker.is_cancelled)
        except SweepCancelled:
            return None
        if not worker.is_cancelled:
            self.app.call_from_thread(self.show_result, result)
        return result

    def _progress(self, done: int, total: int) -> None:
        self.query_one(ProgressBar).update(total=total, progress=done)

    @property
    def running(self) -> bool:
        """True while a sweep worker is still working."""
        return any(w.state in (WorkerState.PENDING, WorkerState.RUNNING)
                   for w in self.workers if w.group == "sweep")

    def show_result(self, result: SweepResult) -> None:
        """Display a finished sweep."""
        self.result = result
        self.query_one("#sweep-state", Static).update(f"done: {result.seed_count} seeds")
        plots = histograms(result) if result.is_full_rank else [None] * len(PARAMETER_NAMES)
        for name, data in zip(PARAMETER_NAMES, plots):
            self.query_one(f"#histogram-{name}", SmallPlot).show(data)
        self.query_one("#sweep-histograms").display = result.is_full_rank
        self.query_one("#sweep-table", Static).update(statistics_table(result))
        summary = result.message
        if result.is_full_rank:
            summary += " " + sign_failure_line(result)
        self.query_one("#sweep-summary", Static).update(summary)

    def on_worker_state_changed(self, event: Worker.StateChanged) -> None:
        """Say so when a sweep was cancelled."""
        if event.worker.group == "sweep" and event.state == WorkerState.CANCELLED and not self.running:
            self.query_one("#sweep-state", Static).update("cancelled")

    def action_cancel(self) -> bool:
        """Stop a running sweep; False when none was running."""
        if not self.running:
            return False
        self.workers.cancel_group(self, "sweep")
        self.query_one("#sweep-state", Static).update("cancelled")
        return True

    def action_back(self) -> None:
        """Escape: cancel a running sweep, or return to the explorer when none runs."""
        if not self.action_cancel():
            self.dismiss()
