"""The seed-sweep view: the current experiment under K noise seeds, as histograms and a table."""

from __future__ import annotations

import math
from contextlib import suppress
from dataclasses import dataclass
from pathlib import Path

from textual import work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal
from textual.css.query import NoMatches
from textual.screen import Screen
from textual.widgets import Label, ProgressBar, Static
from textual.worker import Worker, WorkerState, get_current_worker

from jointid.options import SettingsError, parse_int
from jointid.present.charts import sweep_histograms
from jointid.present.tables import sweep_summary, sweep_table
from jointid.present.text import settings_header
from jointid.studies.sweep import DEFAULT_SEED_COUNT, SweepCancelled, SweepResult, run_sweep
from jointid.synthetic.settings import Settings

from ..widgets.footer import KeyFooter
from ..widgets.plot_guard import MIN_PLOT_SIZE
from ..widgets.small_plots import SmallPlot
from ..widgets.stepper import Stepper, StepRange

EXPLORER_SEED_COUNT_LIMITS = (1, 100_000)
"""Seeds the view accepts (the core allows more): a 100,000-seed sweep still finishes in about a second."""
PROGRESS_STEPS = 50
"""Chunks a sweep is split into, so the progress bar moves even though each chunk is fast."""
MIN_CHUNK = 500
"""Smallest chunk: below it the per-chunk overhead outweighs the work."""
HISTOGRAM_GAP = 1
"""Columns between two histograms side by side (views.tcss, .histogram's right margin)."""


@dataclass(frozen=True)
class SeedCountRange(StepRange):
    """The seed-count control's range; the count is not an experiment setting, so it parses itself."""

    def parse(self, text: str) -> float:
        """Typed text as a whole number of seeds in range, or raise SettingsError."""
        text = text.strip()
        try:
            value = parse_int(text)  # ASCII digits only, as every number field
        except ValueError:
            value = None
        if value is None or not self.low <= value <= self.high:
            raise SettingsError(self.field, f"seeds must be a whole number {self.describe()}; got {text!r}")
        return value


SEED_COUNT_RANGE = SeedCountRange("seeds", *EXPLORER_SEED_COUNT_LIMITS, 100, 1000)
"""K: Left/Right step 100 seeds, Shift 1000; typed values from 1 to 100,000."""


def seeds(count: int) -> str:
    """'1 seed', '1000 seeds'."""
    return f"{count} seed" if count == 1 else f"{count} seeds"


def chunk_size(seed_count: int) -> int:
    """Seeds per chunk for a sweep of seed_count, so progress arrives about PROGRESS_STEPS times."""
    return max(MIN_CHUNK, math.ceil(seed_count / PROGRESS_STEPS))


class SweepScreen(Screen):
    """Seed sweep of the current experiment, run in a worker thread with progress and cancel."""

    CSS_PATH = Path(__file__).parent.parent / "views.tcss"  # read when first opened, not at start-up

    BINDINGS = [
        # Priority: the seed-count field has focus and would otherwise take Escape.
        Binding("escape", "back", "Cancel / back", priority=True,
                tooltip="Cancel a running sweep, otherwise return to the explorer"),
        # Not priority: the seed-count field sees c and g first, in order with the keys before
        # them, and passes them on only while nothing is typed there (Stepper command_keys);
        # so "abc" is typed and refused whole. As priority bindings they were decided on
        # arrival, before the field had taken the keys typed just before.
        Binding("c", "cancel", "Cancel", tooltip="Stop a running sweep"),
        Binding("g", "run", "Run again", tooltip="Run the sweep again with the current seed count"),
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
        yield Static(f"Seed sweep: {settings_header(self.settings)} onward", id="sweep-title", markup=False)
        with Horizontal(id="sweep-controls"):
            yield Label("Seeds (K)", id="sweep-count-label")
            yield Stepper(SEED_COUNT_RANGE, self.seed_count, on_commit=self.commit_seed_count,
                          command_keys="cg", id="sweep-count")
            yield ProgressBar(total=self.seed_count, show_eta=False, id="sweep-progress")
            yield Static("", id="sweep-state", markup=False)
        with Horizontal(id="sweep-histograms"):
            for name in self.settings.joint_model.names:
                yield SmallPlot(id=f"histogram-{name}", classes="histogram")
        yield Static("", id="sweep-table", markup=False)
        yield Static("", id="sweep-summary", markup=False)
        yield KeyFooter()

    def on_resize(self) -> None:
        """Stack the histograms when side by side they would be too narrow to draw (a tall, narrow terminal)."""
        side_by_side = len(self.settings.joint_model.names) * (MIN_PLOT_SIZE[0] + HISTOGRAM_GAP)
        self.set_class(self.size.width < side_by_side, "-stacked")

    def on_mount(self) -> None:
        """Start the first sweep with the seed-count field focused."""
        self.query_one(Stepper).focus()
        self.action_run()

    def commit_seed_count(self, field: str, value: float) -> None:
        """A new seed count (the field's callback): sweep again (an exclusive worker drops the one still running)."""
        self.seed_count = int(value)
        self.query_one(Stepper).show_value(self.seed_count)  # the stepper shows what its owner holds
        self.action_run()

    def action_run(self) -> None:
        """Run the sweep for the current seed count."""
        progress = self.query_one(ProgressBar)
        progress.update(total=self.seed_count, progress=0)
        self.query_one("#sweep-state", Static).update(f"running {seeds(self.seed_count)}…")
        self.sweep(self.seed_count)

    @work(thread=True, exclusive=True, group="sweep")
    def sweep(self, seed_count: int) -> SweepResult | None:
        """Fit every seed in a thread, reporting progress; returns None when cancelled."""
        worker = get_current_worker()

        def progress(done: int, total: int) -> None:
            if not worker.is_cancelled:
                self.app.call_from_thread(self._progress, worker, done, total)

        try:
            result = run_sweep(self.settings, seed_count, chunk_size=chunk_size(seed_count),
                               progress=progress, cancelled=lambda: worker.is_cancelled)
        except SweepCancelled:
            return None
        if not worker.is_cancelled:
            self.app.call_from_thread(self._deliver, worker, result)
        return result

    # The thread's calls run later on the app's loop: by then the sweep may have been replaced
    # or cancelled, or the view closed, its widgets removed before its workers are cancelled
    # (a key storm found this: s then Escape while a sweep finished).

    def _progress(self, worker: Worker, done: int, total: int) -> None:
        if worker.is_cancelled:
            return
        with suppress(NoMatches):  # the view has closed
            self.query_one(ProgressBar).update(total=total, progress=done)

    def _deliver(self, worker: Worker, result: SweepResult) -> None:
        if worker.is_cancelled:
            return
        with suppress(NoMatches):  # the view has closed
            self.show_result(result)

    @property
    def running(self) -> bool:
        """True while a sweep worker is still working."""
        return any(w.state in (WorkerState.PENDING, WorkerState.RUNNING)
                   for w in self.workers if w.group == "sweep")

    def show_result(self, result: SweepResult) -> None:
        """Display a finished sweep."""
        self.result = result
        self.query_one("#sweep-state", Static).update(f"done: {seeds(result.seed_count)}")
        names = result.model.names
        plots = sweep_histograms(result) if result.is_full_rank else [None] * len(names)
        for name, data in zip(names, plots):
            self.query_one(f"#histogram-{name}", SmallPlot).show(data)
        self.query_one("#sweep-histograms").display = result.is_full_rank
        self.query_one("#sweep-table", Static).update(sweep_table(result))
        self.query_one("#sweep-summary", Static).update(sweep_summary(result))

    def on_worker_state_changed(self, event: Worker.StateChanged) -> None:
        """Say so when a sweep was cancelled."""
        if event.worker.group == "sweep" and event.state == WorkerState.CANCELLED and not self.running:
            with suppress(NoMatches):  # cancelled because the view closed
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
