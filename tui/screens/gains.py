"""The gains a controller takes, in their own view: the mechanism's WPILib feedforward (SimpleMotorFeedforward,
ElevatorFeedforward or ArmFeedforward) of the log shown, and
the physical parameters behind a voltage log's gains when the motor is known."""

from __future__ import annotations

from pathlib import Path

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import VerticalScroll
from textual.screen import Screen
from textual.widgets import Static

from ..widgets.footer import KeyFooter
from ..widgets.wide_scroll import WideScroll


class GainsScreen(Screen):
    """Scrollable gains of the log shown; Escape (or g, q) closes them."""

    CSS_PATH = Path(__file__).parent.parent / "views.tcss"  # read when first opened, not at start-up

    BINDINGS = [
        Binding("escape", "close", "Close gains"),
        Binding("g", "close", "Close gains", show=False),
        Binding("q", "close", "Close gains", show=False),
    ]

    def __init__(self, title: str, sections: list[tuple[str, ...]]) -> None:
        """Create the view.

        Args:
            title: What the gains are of: the log's name, or the runs pooled.
            sections: Each section's parts (jointid.present.gains' gains_parts, motor_parts): a heading, then
                tables and code kept whole (scrolled sideways on a narrow screen), the last part its sentences.
        """
        super().__init__()
        self.title_text = title
        self.sections = sections

    @property
    def text(self) -> str:
        """Everything the view shows, as plain text."""
        return "\n\n".join("\n".join(part for part in section if part) for section in self.sections)

    def compose(self) -> ComposeResult:
        """Each section's heading, its wide parts in sideways scrolls, its sentences; the footer."""
        with VerticalScroll() as scroll:
            scroll.border_title = f"Gains: {self.title_text}"
            scroll.border_subtitle = "Tab: the tables, ←/→ their columns, End/Home"
            for heading, *wide, sentences in self.sections:
                yield Static(heading, markup=False)
                for part in wide:
                    with WideScroll(classes="gains--wide"):  # tables and code keep their lines whole
                        yield Static(part, markup=False)
                if sentences:
                    yield Static(sentences + "\n", markup=False)
        yield KeyFooter()

    def on_mount(self) -> None:
        """Focus the scroll view so the arrow keys scroll at once."""
        self.query_one(VerticalScroll).focus()

    def action_close(self) -> None:
        """Return to the explorer."""
        self.dismiss()
