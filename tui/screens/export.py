"""Ctrl+S: the current fit as the command line's JSON plus an SVG screenshot, written atomically."""

from __future__ import annotations

import os
from itertools import count
from pathlib import Path

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Vertical
from textual.screen import ModalScreen
from textual.widgets import Input, Label, Static

from jointid.export import ExportError, write_json, write_text

SUFFIXES = (".json", ".svg")
"""What one export writes: the fit document and the screenshot."""


def free_stem(folder: Path, stem: str) -> Path:
    """folder/stem, or stem-2, stem-3, ... : the first for which no export file exists yet."""
    for number in count(1):
        candidate = folder / (stem if number == 1 else f"{stem}-{number}")
        if not any(candidate.with_name(candidate.name + s).exists() for s in SUFFIXES):
            return candidate
    raise AssertionError("unreachable")


def write_export(folder: str | os.PathLike, stem: str, document: dict, svg: str) -> tuple[Path, Path]:
    """Write stem.json and stem.svg (numbered when taken) atomically; ExportError, never an overwrite."""
    folder = Path(folder).expanduser()
    if not folder.is_dir():
        raise ExportError(f"{folder}: not a folder")
    base = free_stem(folder, stem)
    json_path, svg_path = (base.with_name(base.name + s) for s in SUFFIXES)
    write_json(json_path, document)  # overwrite=False: a file that appeared meanwhile is refused
    try:
        write_text(svg_path, svg)
    except ExportError:
        json_path.unlink()  # keep the pair together: no JSON without its picture
        raise
    return json_path, svg_path


class ExportScreen(ModalScreen[str | None]):
    """Ask for the folder to export into; Enter exports, Escape cancels."""

    DEFAULT_CSS = """
    ExportScreen {
        align: center middle;
    }
    ExportScreen > Vertical {
        width: 80%;
        max-width: 90;
        height: auto;
        border: round $primary;
        border-title-align: left;
        padding: 0 1;
    }
    ExportScreen Static {
        color: $text-muted;
    }
    """

    BINDINGS = [Binding("escape", "cancel", "Cancel", tooltip="Close without exporting")]

    def __init__(self, stem: str, folder: str | None = None) -> None:
        """Create the dialog.

        Args:
            stem: File name the export will use, without suffix.
            folder: Folder shown at first (default: the current directory).
        """
        super().__init__()
        self.stem = stem
        self.folder = folder or os.getcwd()

    def compose(self) -> ComposeResult:
        """Folder field and what will be written."""
        with Vertical() as box:
            box.border_title = "Export the fit (JSON) and a screenshot (SVG)"
            yield Label("Folder (Enter exports):")
            yield Input(value=self.folder, id="export-folder", compact=True)
            yield Static(
                f"Writes {self.stem}.json and {self.stem}.svg; an existing file is never replaced "
                "(a number is added instead). Escape cancels.",
                markup=False,
            )

    def on_input_submitted(self, message: Input.Submitted) -> None:
        """Export into the typed folder."""
        self.dismiss(message.value.strip() or ".")

    def action_cancel(self) -> None:
        """Close without exporting."""
        self.dismiss(None)
