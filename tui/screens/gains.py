"""The gains a controller takes, in their own view: WPILib's ArmFeedforward kS, kG, kV, kA of the log shown, and
the physical parameters behind a voltage log's gains when the motor is known."""

from __future__ import annotations

from pathlib import Path

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import VerticalScroll
from textual.screen import Screen
from textual.widgets import Static

from ..widgets.footer import KeyFooter


class GainsScreen(Screen):
    """Scrollable gains of the log shown; Escape (or g, q) closes them."""

    CSS_PATH = Path(__file__).parent.parent / "views.tcss"  # read when first opened, not at start-up

    BINDINGS = [
        Binding("escape", "close", "Close gains"),
        Binding("g", "close", "Close gains", show=False),
        Binding("q", "close", "Close gains", show=False),
    ]

    def __init__(self, logs, text: str) -> None:
        """Create the view.

        Args:
            logs: The LoadedLogs whose gains are shown.
            text: The gains' text (jointid.present.gains), computed by the owner.
        """
        super().__init__()
        self.logs = logs
        self.text = text

    def compose(self) -> ComposeResult:
        """The gains, one paragraph each, in a focused scroll view; the footer."""
        with VerticalScroll() as scroll:
            scroll.border_title = f"Gains: {self.logs.name}"
            yield Static(self.text, markup=False, id="gains-text")
        yield KeyFooter()

    def on_mount(self) -> None:
        """Focus the scroll view so the arrow keys scroll at once."""
        self.query_one(VerticalScroll).focus()

    def action_close(self) -> None:
        """Return to the explorer."""
        self.dismiss()
