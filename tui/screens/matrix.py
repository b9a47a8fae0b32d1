"""The cross-excitation view: fit on each training motion, predict every motion against truth."""

from __future__ import annotations

from pathlib import Path

from textual.app import ComposeResult
from textual.binding import Binding
from textual.screen import Screen
from textual.widgets import Static

from jointid.present.tables import MATRIX_EXPLANATION, matrix_notes, matrix_table, matrix_title
from jointid.studies.cross_excitation import cross_excitation
from jointid.synthetic.settings import Settings

from ..widgets.footer import KeyFooter


class MatrixScreen(Screen):
    """The cross-excitation table for the current noise, samples and seed."""

    CSS_PATH = Path(__file__).parent.parent / "views.tcss"  # read when first opened, not at start-up

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
        yield Static(matrix_title(self.table), id="matrix-title", markup=False)
        yield Static(matrix_table(self.table), id="matrix-table", markup=False)
        yield Static(matrix_notes(self.table), id="matrix-notes", markup=False)
        yield Static(MATRIX_EXPLANATION, id="matrix-explanation", markup=False)
        yield KeyFooter()

    def action_back(self) -> None:
        """Return to the explorer."""
        self.dismiss()
