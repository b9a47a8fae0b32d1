"""The residual view: training residuals against time, q, qd or qdd, with what structure would mean."""

from __future__ import annotations

from pathlib import Path

from textual.app import ComposeResult
from textual.binding import Binding
from textual.reactive import reactive
from textual.screen import Screen
from textual.widgets import Static

from jointid.estimation.fit import FitResult
from jointid.estimation.residuals import AXES, AXIS_LABELS, residual_data
from jointid.present.charts import residual_scatter, residual_summary

from ..widgets.footer import KeyFooter
from ..widgets.small_plots import SmallPlot

AXIS_KEYS = {axis: str(number) for number, axis in enumerate(AXES, start=1)}
"""Key per axis: 1 time, 2 angle q, 3 velocity qd, 4 acceleration qdd."""


class ResidualScreen(Screen):
    """Training residuals of the current fit against a switchable axis."""

    CSS_PATH = Path(__file__).parent.parent / "views.tcss"  # read when first opened, not at start-up

    BINDINGS = [
        Binding("escape", "back", "Back", tooltip="Return to the explorer"),
        *(
            Binding(key, f"axis('{axis}')", axis, tooltip=f"Residuals against {AXIS_LABELS[axis]}")
            for axis, key in AXIS_KEYS.items()
        ),
    ]

    axis: reactive[str] = reactive("t", init=False)

    def __init__(self, result: FitResult, source: str) -> None:
        """Create the view.

        Args:
            result: The fit whose training residuals are shown.
            source: What the fit came from, for the title: the settings header or "log train.csv".
        """
        super().__init__()
        self.source = source
        self.data = residual_data(result)

    def compose(self) -> ComposeResult:
        """Title, scatter chart, summary, note, footer."""
        yield Static(f"Residuals: {self.source}", id="residual-title", markup=False)
        yield SmallPlot(id="residual-plot")
        yield Static("", id="residual-summary", markup=False)
        yield Static("", id="residual-note", markup=False)
        yield KeyFooter()

    def on_mount(self) -> None:
        """Draw the first axis."""
        self.watch_axis(self.axis)

    def watch_axis(self, axis: str) -> None:
        """Redraw the chart and the note for a new axis."""
        self.query_one(SmallPlot).show(residual_scatter(self.data, axis))
        self.query_one("#residual-summary", Static).update(residual_summary(self.data))
        self.query_one("#residual-note", Static).update(f"What structure would mean: {self.data.note(axis)}")

    def action_axis(self, axis: str) -> None:
        """Show the residuals against an axis."""
        if axis in AXES:
            self.axis = axis

    def action_back(self) -> None:
        """Return to the explorer."""
        self.dismiss()
