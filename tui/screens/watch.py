"""The watch view (`jointid watch` on a terminal): a joint fitted while it moves, refreshed several times a second.

The watch runs in a thread worker (the source's polls and the refits never hold the keys up); each refresh is
handed to the screen as a message, and a refresh that arrives while the last is still being drawn replaces it,
so a slow terminal shows fewer refreshes, never older ones. The screen holds the only state: the latest refresh.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from textual import work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical, VerticalScroll
from textual.content import Content
from textual.message import Message
from textual.screen import Screen
from textual.widgets import Markdown, Static

from jointid.present.readouts import precision, readouts
from jointid.present.watch import (
    CONVERGENCE_KINDS,
    closing_lines,
    convergence_chart,
    counts_text,
    recent_chart,
    saved_brief,
    saved_sentence,
)
from jointid.text_safety import shown_name

from ..sizes import MIN_SIZE, size_classes
from ..widgets.charts import TorqueChart
from ..widgets.convergence import ConvergenceChart
from ..widgets.fitting import FittingLine
from ..widgets.footer import KeyFooter
from ..widgets.readouts import ReadoutPanel

if TYPE_CHECKING:
    from jointid.present.watch import Saved
    from jointid.studies.watch_refresh import WatchRefresh

WAITING = "Waiting for the first samples…"
"""The notes before the first refresh."""
NOTIFIED_EVENTS = ("gap", "gone", "reconnect", "dropped", "truncated", "replaced", "lost", "stopped reading")
"""Words of the source's events that also pop up as a notification: what interrupts or loses data."""
STATUS_LINES = 2
"""Rows the status takes: the counts and the latest event, or what became of the samples."""


def new_events(shown: tuple[str, ...], latest: tuple[str, ...]) -> tuple[str, ...]:
    """The events of `latest` that `shown` did not have: the source's list only grows at its end and loses its
    oldest (it is bounded), so the new ones follow the longest end of `shown` that `latest` starts with."""
    for overlap in range(min(len(shown), len(latest)), 0, -1):
        if shown[-overlap:] == latest[:overlap]:
            return latest[overlap:]
    return latest


class WatchScreen(Screen):
    """The readouts, the recent torque chart and the convergence chart of a live identification."""

    BINDINGS = [
        Binding("q", "stop", "Stop & save", priority=True,
                tooltip="Stop watching, fit what arrived, save it (--save) and leave"),
        Binding("ctrl+c", "stop", "Stop & save", show=False, priority=True),
        Binding("v", "convergence", "Estimates/errors", priority=True,
                tooltip="Switch the lower chart between each estimate over time and each relative error"),
        Binding("question_mark", "help", "Help", key_display="?", priority=True,
                tooltip="Keys and what the watch view shows"),
    ]

    class Refreshed(Message):
        """A refresh is waiting in `WatchScreen.latest` (posted from the watch thread)."""

    class Finished(Message):
        """The watch stopped and its samples were saved, or not (posted from the watch thread)."""

        def __init__(self, stopped_by: str, saved: Saved) -> None:
            super().__init__()
            self.stopped_by = stopped_by
            self.saved = saved

    def __init__(self, plan) -> None:
        """Create the view.

        Args:
            plan: The watch to run (jointid.cli.live_plan.WatchPlan or one alike: `watch(on_refresh)`, `stop()`,
                `save()`, `description`, `effort`).
        """
        super().__init__()
        self.plan = plan
        self.latest: WatchRefresh | None = None
        """The newest refresh, written by the watch thread, read when its message arrives."""
        self.shown: WatchRefresh | None = None
        """The refresh on screen."""
        self.convergence_kind = CONVERGENCE_KINDS[0]
        self.stopped_by: str | None = None
        self.saved: Saved | None = None
        """What became of the samples once the watch stopped (the command prints it after the view closes)."""
        self._posted = False
        self._leave_when_done = False
        self._events: tuple[str, ...] = ()

    def compose(self) -> ComposeResult:
        """Title, side panel (readouts and the watch's notes), two charts, status, footer."""
        self.update_classes(size_classes(*self.app.size))
        yield Static(f"jointid watch · {shown_name(self.plan.description)}", id="title", markup=False)
        with Horizontal(id="main"):
            with Vertical(id="side"):
                # One row per parameter at every size: the notes under the readouts need the rows, and a
                # voltage fit's labels ('Fitted acceleration gain (V s²/rad)') pushed its values to rows of their own.
                yield ReadoutPanel(id="readouts", compact=True)
                yield Static(WAITING, id="watch-notes", markup=False)
            with Vertical(id="charts"):
                yield TorqueChart(id="recent-chart")
                yield ConvergenceChart(id="convergence-chart")
        yield FittingLine(id="status", min_lines=STATUS_LINES)
        yield Static("", id="too-small", markup=False)
        yield KeyFooter()

    def on_mount(self) -> None:
        """Start watching."""
        self.show_status()
        self.run_watch()

    def on_resize(self) -> None:
        """The size classes (narrow side panel); a plain message below the smallest size."""
        width, height = self.size
        classes = size_classes(width, height)
        self.update_classes(classes)
        if classes["-too-small"]:
            self.query_one("#too-small", Static).update(
                f"Please enlarge the terminal.\n\nThe watch view needs at least {MIN_SIZE[0]} x {MIN_SIZE[1]} "
                f"characters; this one is {width} x {height}.\n\nPress q to stop watching and save.")

    # --- the watch thread ---------------------------------------------------------------

    @work(thread=True, exclusive=True, group="watch")
    def run_watch(self) -> None:
        """Watch until stopped or the source ends, then save; runs off the UI thread."""
        try:
            stopped_by = self.plan.watch(self.deliver)
        finally:
            saved = self.plan.save()  # whatever stopped the watch, even a failing fit: nothing received is lost
        self.post_message(self.Finished(stopped_by, saved))

    def deliver(self, refresh: WatchRefresh) -> None:
        """Hand a refresh to the screen (from the watch thread): the newest replaces one not yet shown."""
        self.latest = refresh
        if not self._posted:
            self._posted = True
            self.post_message(self.Refreshed())

    def on_watch_screen_refreshed(self, _message: Refreshed) -> None:
        """Show the newest refresh."""
        self._posted = False
        if self.latest is not None and self.latest is not self.shown:
            self.show_refresh(self.latest)

    def on_watch_screen_finished(self, message: Finished) -> None:
        """Show the final refresh and what was saved; leave if q asked to."""
        self.stopped_by, self.saved = message.stopped_by, message.saved
        if self.latest is not None and self.latest is not self.shown:
            self.show_refresh(self.latest)
        self.show_status()
        if self._leave_when_done:
            self.app.exit(self.app.return_code)
            return
        if message.saved.path is None and self.plan.save_path is not None:  # the status says it; a failure pops up
            self.notify(saved_sentence(message.saved), title="Not saved", severity="error")
        failure = getattr(self.plan.session, "failure", None)
        if failure is not None:
            self.notify(failure, title="Source", severity="error")

    # --- what is shown ---------------------------------------------------------------------

    def show_refresh(self, refresh: WatchRefresh) -> None:
        """Push one refresh down to every widget."""
        self.shown = refresh
        result = refresh.result
        if result is not None:
            self.query_one(ReadoutPanel).show(readouts(result), precision(result))
        chart = recent_chart(refresh, self.plan.effort)
        if chart is not None:
            self.query_one("#recent-chart", TorqueChart).show(chart)
        self.query_one(ConvergenceChart).show(convergence_chart(refresh, self.convergence_kind))
        notes = closing_lines(refresh)
        self.query_one("#watch-notes", Static).update("\n".join(notes) if notes else WAITING)
        for event in new_events(self._events, refresh.events):
            if any(word in event for word in NOTIFIED_EVENTS):  # the status line has every event; these also pop up
                self.notify(event, title="Source", severity="warning")
        self._events = refresh.events
        self.show_status()

    def show_status(self) -> None:
        """The counts and the latest event while watching; how it stopped and what was saved after."""
        refresh = self.shown
        counts = WAITING if refresh is None else counts_text(refresh)
        if self.saved is not None:
            seconds = (f"Stopped ({self.stopped_by}). {saved_sentence(self.saved)} q leaves.",
                       f"Stopped ({self.stopped_by}): {saved_brief(self.saved)}. q leaves.")
        elif self._leave_when_done:
            seconds = ("Stopping: fitting what arrived and saving…",)
        else:
            latest = refresh.events[-1] if refresh is not None and refresh.events else None
            # The latest event where it fits the two rows, else only the key (the notifications have the rest).
            seconds = ((f"Watching · {latest} · q stops and saves",) if latest else ()) + (
                "Watching · q stops and saves",)
        self.query_one("#status", FittingLine).show(tuple(Content(f"{counts}\n{second}") for second in seconds))

    # --- the keys ---------------------------------------------------------------------------

    def action_stop(self) -> None:
        """Stop watching and save (the thread finishes the last refresh first); leave once done. A second press
        while it saves changes nothing: the samples are never left half-written."""
        if self.saved is not None:
            self.app.exit(self.app.return_code)
            return
        self._leave_when_done = True
        self.plan.stop()
        self.show_status()

    def action_convergence(self) -> None:
        """Switch the lower chart between estimates and errors."""
        index = CONVERGENCE_KINDS.index(self.convergence_kind)
        self.convergence_kind = CONVERGENCE_KINDS[(index + 1) % len(CONVERGENCE_KINDS)]
        if self.shown is not None:
            self.query_one(ConvergenceChart).show(convergence_chart(self.shown, self.convergence_kind))

    def action_help(self) -> None:
        """The watch view's help."""
        self.app.push_screen(WatchHelpScreen(self.BINDINGS))


WATCH_HELP_FILE = Path(__file__).parent.parent / "help_watch.md"
"""The watch view's help; `{keys}` is filled in from its bindings."""


def watch_help_markdown(bindings: list[Binding]) -> str:
    """The watch view's help text with its keys."""
    rows = [(binding.key_display or binding.key, binding.tooltip) for binding in bindings if binding.tooltip]
    keys = "\n".join(f"- `{key}`: {does}" for key, does in rows)
    return WATCH_HELP_FILE.read_text(encoding="utf-8").format(keys=keys)


class WatchHelpScreen(Screen):
    """The watch view's help; Escape (or ?, q) closes it."""

    CSS_PATH = Path(__file__).parent.parent / "views.tcss"

    BINDINGS = [
        Binding("escape", "close", "Close help"),
        Binding("question_mark", "close", "Close help", key_display="?", show=False),
        Binding("q", "close", "Close help", show=False),
    ]

    def __init__(self, bindings: list[Binding]) -> None:
        super().__init__()
        self.view_bindings = bindings

    def compose(self) -> ComposeResult:
        """The help Markdown in a focused scroll view, and the footer."""
        with VerticalScroll() as scroll:
            scroll.border_title = "Help"
            yield Markdown(watch_help_markdown(self.view_bindings))
        yield KeyFooter()

    def on_mount(self) -> None:
        """Focus the scroll view so the arrow keys scroll at once."""
        self.query_one(VerticalScroll).focus()

    def action_close(self) -> None:
        """Back to the watch."""
        self.dismiss()
