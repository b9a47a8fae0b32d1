"""The notes of a log's fit in their own view: what was read and how, what was left out, the sensitivity check."""

from __future__ import annotations

from pathlib import Path

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import VerticalScroll
from textual.screen import Screen
from textual.widgets import Static

from jointid.present.summary import log_notes_text

from ..widgets.footer import KeyFooter


class NotesScreen(Screen):
    """Scrollable notes of the log shown; Escape (or n, q) closes them."""

    CSS_PATH = Path(__file__).parent.parent / "views.tcss"  # read when first opened, not at start-up

    BINDINGS = [
        Binding("escape", "close", "Close notes"),
        Binding("n", "close", "Close notes", show=False),
        Binding("q", "close", "Close notes", show=False),
    ]

    def __init__(self, logs) -> None:
        """Create the view.

        Args:
            logs: The LoadedLogs whose notes are shown.
        """
        super().__init__()
        self.logs = logs

    def compose(self) -> ComposeResult:
        """The notes, one paragraph each, in a focused scroll view; the footer."""
        with VerticalScroll() as scroll:
            scroll.border_title = f"Notes: {self.logs.name}"
            yield Static(log_notes_text(self.logs), markup=False)
        yield KeyFooter()

    def on_mount(self) -> None:
        """Focus the scroll view so the arrow keys scroll at once."""
        self.query_one(VerticalScroll).focus()

    def action_close(self) -> None:
        """Return to the explorer."""
        self.dismiss()
