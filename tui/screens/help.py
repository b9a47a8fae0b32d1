"""The help screen: keys, controls, model and the lesson's three things to try."""

from __future__ import annotations

from pathlib import Path

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import VerticalScroll
from textual.screen import Screen
from textual.widgets import Markdown

from jointid.cli.serve_command import DEFAULT_IDLE_TIMEOUT
from jointid.options import DEFAULT_ORDER, default_log_model

from ..palette import PHYSICS_STOPS, TOUR
from ..ranges import NOISE_RANGE, SAMPLES_RANGE, SEED_RANGE
from ..widgets.footer import KeyFooter
from ..widgets.stepper import Stepper

HELP_FILE = Path(__file__).parent.parent / "help.md"
"""Markdown source of the help text; `{keys}`, the ranges, the tour's length, the smoothing order and the log
defaults' models are filled in from the code."""
WEB_HELP_FILE = Path(__file__).parent.parent / "help_web.md"
"""What differs in a browser (`jointid serve`), added to the help there; `{idle_minutes}` is filled in."""


def keys_table(bindings: list[Binding]) -> str:
    """A Markdown list of the main screen's keys (its `bindings`) and the number fields' keys."""
    rows = [("Tab / Shift+Tab", "move between controls"), ("Up / Down", "choose a motion in the list")]
    for binding in bindings:
        if binding.tooltip:  # the others only explain why a key is off for now
            rows.append((binding.key_display or binding.key, binding.tooltip))
    for binding in Stepper.BINDINGS:
        rows.append((binding.key.replace("shift+", "Shift+").title(), f"in a number field: {binding.description.lower()}"))
    rows.append(("Enter", "in a number field: commit the typed value"))
    rows.append(("Ctrl+P", "command palette: every action and the guided tour"))
    return "\n".join(f"- `{key}`: {does}" for key, does in rows)


def sentence_start(phrase: str) -> str:
    """The phrase with its first letter capitalised and the rest as it is (str.capitalize writes 'N m' as 'n m')."""
    return phrase[:1].upper() + phrase[1:]


def help_markdown(bindings: list[Binding], web: bool = False) -> str:
    """The help text with the main screen's keys (`bindings`), the ranges and the defaults taken from the code; in
    a browser (`web`) followed by what differs there."""
    text = HELP_FILE.read_text(encoding="utf-8")
    if web:
        text += "\n" + WEB_HELP_FILE.read_text(encoding="utf-8")
    return text.format(
        keys=keys_table(bindings),
        noise_range=sentence_start(NOISE_RANGE.describe()),
        samples_range=sentence_start(SAMPLES_RANGE.describe()),
        seed_range=sentence_start(SEED_RANGE.describe()),
        tour_stops=len(TOUR) + len(PHYSICS_STOPS),
        lesson_stops=len(TOUR),
        order=DEFAULT_ORDER,
        log_model=default_log_model("torque"),
        voltage_log_model=default_log_model("voltage"),
        idle_minutes=f"{DEFAULT_IDLE_TIMEOUT / 60:g}",
    )


class HelpScreen(Screen):
    """Scrollable help; Escape (or ?, q) closes it."""

    CSS_PATH = Path(__file__).parent.parent / "views.tcss"  # read when first opened, not at start-up

    BINDINGS = [
        Binding("escape", "close", "Close help"),
        Binding("question_mark", "close", "Close help", key_display="?", show=False),
        Binding("q", "close", "Close help", show=False),
    ]

    def __init__(self, bindings: list[Binding]) -> None:
        """Create the help screen.

        Args:
            bindings: The main screen's key bindings, listed in the help.
        """
        super().__init__()
        self.main_bindings = bindings

    def compose(self) -> ComposeResult:
        """The help Markdown in a focused scroll view, and the footer."""
        with VerticalScroll() as scroll:
            scroll.border_title = "Help"
            yield Markdown(help_markdown(self.main_bindings, web=self.app.is_web))
        yield KeyFooter()

    def on_mount(self) -> None:
        """Focus the scroll view so the arrow keys scroll at once."""
        self.query_one(VerticalScroll).focus()

    def action_close(self) -> None:
        """Return to the explorer."""
        self.dismiss()
