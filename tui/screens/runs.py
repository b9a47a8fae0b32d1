"""Several runs of one joint in their own view: each run's fit beside the pooled one, the scatter, who disagrees."""

from __future__ import annotations

from pathlib import Path
from typing import Callable

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import VerticalScroll
from textual.screen import Screen
from textual.widgets import Static

from jointid.present.runs import runs_parts

from ..widgets.footer import KeyFooter
from ..widgets.wide_scroll import WideScroll

MAX_KEYED_RUNS = 9
"""Runs the digit keys reach (1 to 9); further runs are in the table, shown with their own key only."""


class RunsScreen(Screen):
    """The per-run table and the pooled fit; a digit shows that run on the main screen, Escape (or u, q) closes."""

    CSS_PATH = Path(__file__).parent.parent / "views.tcss"  # read when first opened, not at start-up

    BINDINGS = [
        Binding("escape", "close", "Close runs"),
        Binding("u", "close", "Close runs", show=False),
        Binding("q", "close", "Close runs", show=False),
        *(Binding(str(k), f"show_run({k - 1})", "Show run", show=k == 1, key_display="1-9" if k == 1 else None)
          for k in range(1, MAX_KEYED_RUNS + 1)),
    ]

    def __init__(self, runs, on_show: Callable[[int], None]) -> None:
        """Create the view.

        Args:
            runs: The studies.runs.PooledRuns shown.
            on_show: Called with a run's index when a digit picks it.
        """
        super().__init__()
        self.runs = runs
        self.on_show = on_show

    def compose(self) -> ComposeResult:
        """The table and its sentences in a focused scroll view, a line on the keys, the footer."""
        heading, table, *sentences = runs_parts(self.runs)
        keys = "; ".join(f"{k + 1}: {name}" for k, name in enumerate(self.runs.names[:MAX_KEYED_RUNS]))
        with VerticalScroll() as scroll:
            scroll.border_title = f"{len(self.runs.runs)} runs of one joint"
            scroll.border_subtitle = "Tab: the table, ←/→ its columns"
            yield Static(heading, markup=False)
            with WideScroll(id="runs-table"):  # the table keeps its columns; a narrow screen scrolls it
                yield Static(table, markup=False)
            yield Static("\n".join(sentences), markup=False)
            yield Static(f"Show a run's own fit on the main screen: {keys}.", id="runs-keys", markup=False)
        yield KeyFooter()

    def on_mount(self) -> None:
        """Focus the scroll view so the arrow keys scroll at once."""
        self.query_one(VerticalScroll).focus()

    def check_action(self, action: str, parameters: tuple) -> bool | None:
        """A digit beyond the runs does nothing."""
        if action == "show_run":
            return parameters[0] < len(self.runs.runs)
        return True

    def action_show_run(self, index: int) -> None:
        """Show one run on the main screen and return there."""
        self.dismiss()
        self.on_show(index)

    def action_close(self) -> None:
        """Return to the explorer."""
        self.dismiss()
