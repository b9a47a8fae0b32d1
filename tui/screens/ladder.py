"""The model-ladder view: every model fitted to the same data, BIC's choice, and each one simulated."""

from __future__ import annotations

from pathlib import Path

from textual import work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import VerticalScroll
from textual.screen import Screen
from textual.widgets import Static
from textual.worker import get_current_worker

from jointid.model.truth import TrueJoint
from jointid.present.comparison import comparison_sentences, comparison_table, simulation_table
from jointid.samples import JointData
from jointid.studies.ladder import Comparison, compare_log, compare_models, compare_pooled
from jointid.studies.simulation import DEFAULT_HORIZON, simulate_model

from ..widgets.footer import KeyFooter

SIMULATION_NOTE = (
    "Simulation: each fitted model, driven by the true torque of the validation motion and restarted from "
    "the true state every second, against the true angle (RMS; windows off by more than 1 rad count as "
    "diverged). Coulomb terms' sign(qd) is smoothed as tanh(qd/0.01) for the integrator."
)
"""What the simulation column means, under its table."""
WIDE_TABLE = 100
"""Columns from which the comparison table shows each model's terms."""


class LadderScreen(Screen):
    """The comparison of the ladder's models on the data the explorer shows, with a simulation per model."""

    CSS_PATH = Path(__file__).parent.parent / "views.tcss"  # read when first opened, not at start-up

    BINDINGS = [
        Binding("escape", "back", "Back", tooltip="Return to the explorer"),
        Binding("l", "back", "Back", show=False),
    ]

    def __init__(self, title: str, training: JointData | None = None, heldout: JointData | None = None, *,
                 noise_bound: float | None = None, joint: TrueJoint | None = None, logs=None, runs=None) -> None:
        """Create the view.

        Args:
            title: What the data are (the settings header, or the log's name).
            training: The synthetic data every model is fitted to (None with `logs`).
            heldout: The synthetic data every model predicts, or None.
            noise_bound: The known noise bound (synthetic data), for expected standard errors.
            joint: The synthetic joint to simulate against; None for a log (no true torque).
            logs: A fitted log (jointid.studies.log_fit.LoadedLogs), compared as `jointid compare --csv` compares
                it: through its fit's pipeline, its held-out log through the same one.
            runs: Several runs of one joint (jointid.studies.runs.PooledRuns), compared pooled as `jointid compare`
                compares them.
        """
        super().__init__()
        self.title_text = title
        self.comparison: Comparison = (compare_pooled(runs.runs) if runs is not None else
                                       compare_log(logs) if logs is not None else
                                       compare_models(training, heldout, noise_bound=noise_bound))
        self.joint = joint
        self.simulations: dict = {}

    def compose(self) -> ComposeResult:
        """Title, the comparison table, what it shows, the simulations, footer."""
        yield Static(f"Model ladder: {self.title_text}", id="ladder-title", markup=False)
        with VerticalScroll(id="ladder-body"):
            yield Static(comparison_table(self.comparison, compact=self.app.size.width < WIDE_TABLE),
                         id="ladder-table", markup=False)
            yield Static(" ".join(comparison_sentences(self.comparison)), id="ladder-sentences", markup=False)
            yield Static("", id="ladder-simulation", markup=False)
            yield Static("", id="ladder-simulation-note", markup=False)
        yield KeyFooter()

    def on_resize(self) -> None:
        """The table without its terms column below WIDE_TABLE columns."""
        self.query_one("#ladder-table", Static).update(
            comparison_table(self.comparison, compact=self.size.width < WIDE_TABLE))

    def on_mount(self) -> None:
        """Start the simulations (synthetic data only: a log has no true torque to drive them)."""
        if self.joint is None:
            self.query_one("#ladder-simulation", Static).update(
                "Simulation check: unavailable for a log (it needs the true torque of a known motion).")
            return
        self.query_one("#ladder-simulation-note", Static).update(SIMULATION_NOTE)
        self.show_simulations()
        self.simulate()

    def show_simulations(self) -> None:
        """The simulation table with the models done so far."""
        self.query_one("#ladder-simulation", Static).update(
            simulation_table(self.comparison, self.simulations, DEFAULT_HORIZON))

    @work(thread=True, exclusive=True, group="ladder-simulation")
    def simulate(self) -> None:
        """Simulate each model off the main thread, showing each result as it arrives."""
        worker = get_current_worker()
        for row in self.comparison.rows:
            if worker.is_cancelled:
                return
            check = simulate_model(row.model, row.solution.estimate, self.joint)
            self.app.call_from_thread(self._simulated, row.model.name, check)

    def _simulated(self, name: str, check) -> None:
        self.simulations[name] = check
        self.show_simulations()

    def action_back(self) -> None:
        """Return to the explorer (a running simulation is dropped)."""
        self.workers.cancel_group(self, "ladder-simulation")
        self.dismiss()
