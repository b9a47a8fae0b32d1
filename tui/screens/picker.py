"""What the pickers shown after Ctrl+O chooses a bag or a data log share: a box over the explorer whose list is
filled once a worker has surveyed the file, a notification and no load when it cannot be used, Escape to cancel."""

from __future__ import annotations

import threading
from typing import ClassVar

from textual.binding import Binding
from textual.screen import ModalScreen


class SurveyPicker(ModalScreen):
    """A picker whose subclass surveys its file in `survey` (a worker started on mount) and dismisses with what
    was chosen, or None."""

    # Textual's type selectors match subclasses too: every picker gets this box.
    DEFAULT_CSS = """
    SurveyPicker {
        align: center middle;
    }
    SurveyPicker > Vertical {
        width: 90%;
        max-width: 100;
        height: auto;
        max-height: 90%;
        border: round $primary;
        border-title-align: left;
        padding: 0 1;
    }
    SurveyPicker OptionList {
        height: auto;
        max-height: 16;
    }
    SurveyPicker Static {
        color: $text-muted;
    }
    """

    BINDINGS: ClassVar = [Binding("escape", "cancel", "Cancel", tooltip="Close without loading")]

    def __init__(self, path: str) -> None:
        """Create the picker of the file at `path`."""
        super().__init__()
        self.path = path
        self.closed = threading.Event()
        """Set when the picker closes, so a survey that checks it stops at its next progress report."""

    def on_mount(self) -> None:
        """Survey the file off the main thread."""
        self.survey()

    def survey(self) -> None:
        """Read what the list offers (a subclass's worker)."""
        raise NotImplementedError

    def fail(self, problem: str) -> None:
        """Say why the file cannot be used and close."""
        self.notify(problem, title="Log not loaded", severity="error")
        self.dismiss(None)

    def on_unmount(self) -> None:
        """Stop a survey still reading."""
        self.closed.set()

    def action_cancel(self) -> None:
        """Close without loading."""
        self.closed.set()
        self.dismiss(None)
