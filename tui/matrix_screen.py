"""The cross-excitation view: fit on each training motion, predict every motion against truth."""

from __future__ import annotations

from pathlib import Path

from textual.app import ComposeResult
from textual.binding import Binding
from textual.screen import Screen
from textual.widgets import Static

from jointid.cross_excitation import CrossExcitationTable, cross_excitation
from jointid.fit import format_number
from jointid.motions import ALL_MOTIONS, VALIDATION_SAMPLES
from jointid.report import UNAVAILABLE
from jointid.settings import Settings

from .footer import KeyFooter
from .tables import text_table

TRAINING_MARK = "*"
"""Marks an entry evaluated on the motion its row was fitted on (as `jointid matrix` does)."""

COLUMN_TITLES = {"rich": "rich motion", "slow": "slow motion", "test": "validation"}
"""Column headings per prediction motion."""

EXPLANATION = (
    "Each row fits one motion at this noise, sample count and seed; each column is the torque "
    "RMSE (N m) of its predictions against a motion's noiseless truth. Only the unmarked entries "
    "test motions the fit never saw."
)
"""The one-line explanation under the table."""


def cell_text(rmse: float | None, is_training_data: bool) -> str:
    """An entry: the RMSE, marked when it is training data, or 'unavailable'."""
    if rmse is None:
        return UNAVAILABLE
    return format_number(rmse) + (f" {TRAINING_MARK}" if is_training_data else "  ")


def matrix_table(table: CrossExcitationTable) -> str:
    """The 3x3 RMSE table as aligned text, one row per training motion."""
    header = ["fitted on", *(COLUMN_TITLES[m] for m in table.prediction_motions)]
    rows = [
        [f"{ALL_MOTIONS[row.training_motion].label.lower()} (rank {row.fit.rank})",
         *(cell_text(cell.rmse, cell.is_training_data) for cell in row.cells)]
        for row in table.rows
    ]
    return text_table(header, rows)


def matrix_notes(table: CrossExcitationTable) -> str:
    """The legend: what the mark means, where each column's states come from, unavailable rows."""
    missing = [ALL_MOTIONS[row.training_motion].label.lower() for row in table.rows if not row.available]
    lines = [
        f"{TRAINING_MARK} training data: the fit saw these states (with noisy torques); not a held-out test.",
        f"Rich and slow columns: {table.settings.samples} samples at the training instants; "
        f"validation: its {VALIDATION_SAMPLES} states.",
    ]
    if missing:
        lines.append(f"{', '.join(missing).capitalize()}: rank below 3, no unique fit, so no predictions.")
    return "\n".join(lines)


class MatrixScreen(Screen):
    """The cross-excitation table for the current noise, samples and seed."""

    CSS_PATH = Path(__file__).with_name("views.tcss")  # read when first opened, not at start-up

    BINDINGS = [
        Binding("escape", "back", "Back", tooltip="Return to the explorer"),
        Binding("m", "back", "Back", show=False),
    ]

    def __init__(self, settings: Settings) -> None:
        """Create the view.

        Args:
            settings: Noise, samples and seed for every row (its motion is not used).
        """
        super().__init__()
        self.settings = settings
        self.table = cross_excitation(settings)

    def compose(self) -> ComposeResult:
        """Title, table, legend, explanation, footer."""
        settings = self.settings
        yield Static(
            f"Cross-excitation: prediction RMSE (N m); noise {settings.noise:.2f} N m, "
            f"{settings.samples} samples, seed {settings.seed}",
            id="matrix-title", markup=False,
        )
        yield Static(matrix_table(self.table), id="matrix-table", markup=False)
        yield Static(matrix_notes(self.table), id="matrix-notes", markup=False)
        yield Static(EXPLANATION, id="matrix-explanation", markup=False)
        yield KeyFooter()

    def action_back(self) -> None:
        """Return to the explorer."""
        self.dismiss()
