"""The progress dialog shown while a log loads; Escape asks the loader to stop, or drops a fit under way."""

from __future__ import annotations

import os
import threading

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Vertical
from textual.screen import ModalScreen
from textual.widgets import Label, ProgressBar, Static

from jointid.text_safety import shown_name


class LoadingScreen(ModalScreen[None]):
    """A progress bar over the explorer while a worker reads a log; the explorer stays as it was."""

    DEFAULT_CSS = """
    LoadingScreen {
        align: center middle;
    }
    LoadingScreen > Vertical {
        width: 60;
        height: auto;
        border: round $primary;
        padding: 0 1;
    }
    LoadingScreen Label, LoadingScreen Static {
        width: 1fr;
    }
    LoadingScreen Static {
        color: $text-muted;
    }
    """

    BINDINGS = [Binding("escape", "cancel", "Cancel loading", tooltip="Stop reading the log; keep the current data")]

    def __init__(self, path: str, chooser: ModalScreen | None = None) -> None:
        """Create the dialog.

        Args:
            path: The file being read.
            chooser: The dialog the file was chosen in (Ctrl+O's), closed once the log is shown.
        """
        super().__init__()
        self.path = path
        self.cancelled = threading.Event()
        """Set by Escape; the loader checks it between chunks."""
        self.chooser = chooser
        """The dialog the file was chosen in, closed once the log is shown; it stays when the file cannot be."""

    def compose(self) -> ComposeResult:
        """File name, progress bar, hint."""
        with Vertical():
            yield Label(f"Loading {shown_name(os.path.basename(self.path))}", markup=False)
            yield ProgressBar(total=None, show_eta=False, id="load-progress")
            yield Static("Escape cancels; the current data stay.", markup=False, id="load-hint")

    @property
    def hint(self) -> Static:
        """The line under the bar; by id, since the file name's Label is a Static too and comes first."""
        return self.query_one("#load-hint", Static)

    def advance(self, done: int, total: int) -> None:
        """Show bytes read so far (called on the main thread); once all is read, that the fit is under way."""
        self.query_one(ProgressBar).update(total=max(total, 1), progress=done)
        if done >= total and not self.cancelled.is_set():
            self.hint.update("Read; fitting. Escape drops the fit when it ends.")

    def action_cancel(self) -> None:
        """Ask the loader to stop at its next chunk; after the reading, the fit runs on and its result is dropped."""
        self.cancelled.set()
        bar = self.query_one(ProgressBar)
        read = bar.total is not None and bar.progress >= bar.total
        self.hint.update("Cancelling: the fit cannot stop part-way; its result will be dropped."
                                      if read else "Cancelling…")
