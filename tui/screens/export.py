"""Ctrl+S: the current fit as the command line's JSON plus an SVG screenshot, written atomically."""

from __future__ import annotations

import os
import stat
from itertools import count
from pathlib import Path

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Vertical
from textual.screen import ModalScreen
from textual.widgets import Input, Label, Static

from jointid.files import (
    AlreadyExists,
    ExportError,
    json_text,
    remove_stale_temporaries,
    shown_path,
    write_texts,
)

from ..widgets.footer import KeyFooter

SUFFIXES = (".json", ".svg")
"""What one export writes: the fit document and the screenshot."""
NAME_ATTEMPTS = 100
"""Free names tried when files keep appearing under the chosen one while writing (a busy folder)."""


def free_stem(folder: Path, stem: str) -> Path:
    """folder/stem, or stem-2, stem-3, ... : the first for which no export file's name is taken yet.

    A name is taken by anything at all, a dangling symlink included: the export
    never writes through or replaces a link, so such a name is skipped, not refused.
    """
    for number in count(1):
        candidate = folder / (stem if number == 1 else f"{stem}-{number}")
        if not any(os.path.lexists(candidate.with_name(candidate.name + s)) for s in SUFFIXES):
            return candidate
    raise AssertionError("unreachable")


def export_folder(typed: str | os.PathLike) -> Path:
    """The folder a typed path names, `~` expanded; ExportError with one line when it is not an existing folder.

    Every way a typed path can fail (`~nosuchuser`, a name longer than the system allows, a NUL byte, a folder
    we may not look into) is an ExportError, the one error the explorer turns into a notification.
    """
    try:
        folder = Path(typed).expanduser()
    except RuntimeError:  # Path.expanduser's way of saying there is no such user
        raise ExportError(f"{shown_path(typed)}: no such user, so no home folder to expand ~ to") from None
    try:
        is_folder = stat.S_ISDIR(os.stat(folder).st_mode)
    except FileNotFoundError:
        raise ExportError(f"{shown_path(folder)}: no such folder") from None
    except (OSError, ValueError) as error:  # e.g. a name too long; ValueError: a NUL byte
        raise ExportError(f"{shown_path(folder)}: cannot use this folder: {getattr(error, 'strerror', None) or error}") \
            from None
    if not is_folder:
        raise ExportError(f"{shown_path(folder)}: not a folder")
    return folder


def write_export(folder: str | os.PathLike, stem: str, document: dict, svg: str) -> tuple[Path, Path]:
    """Write stem.json and stem.svg (numbered when taken) as a pair: both or neither; ExportError, never an overwrite."""
    folder = export_folder(folder)
    remove_stale_temporaries(str(folder))  # first, so the name of a killed export's orphan is free again
    texts = (json_text(document), svg)
    for _ in range(NAME_ATTEMPTS):
        base = free_stem(folder, stem)
        json_path, svg_path = (base.with_name(base.name + s) for s in SUFFIXES)
        try:
            write_texts({json_path: texts[0], svg_path: texts[1]})
        except AlreadyExists:
            continue  # a file appeared under this name meanwhile: take the next free one
        return json_path, svg_path
    raise ExportError(f"{shown_path(folder)}: no free name for {stem}.json and {stem}.svg")


def write_report_page(folder: str | os.PathLike, stem: str, page: str) -> Path:
    """Write stem.html (or stem-2.html, ... when taken) into `folder`; ExportError, never an overwrite."""
    folder = export_folder(folder)
    remove_stale_temporaries(str(folder))
    for number in range(1, NAME_ATTEMPTS + 1):
        path = folder / (f"{stem}.html" if number == 1 else f"{stem}-{number}.html")
        if os.path.lexists(path):
            continue
        try:
            write_texts({path: page})
        except AlreadyExists:
            continue  # it appeared meanwhile: take the next free name
        return path
    raise ExportError(f"{shown_path(folder)}: no free name for {stem}.html")


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
        """Folder field, what will be written, and the dialog's own keys over the explorer's footer."""
        with Vertical() as box:
            box.border_title = "Export the fit (JSON) and a screenshot (SVG)"
            yield Label("Folder (Enter exports):")
            yield Input(value=self.folder, id="export-folder", compact=True)
            yield Static(
                f"Writes {self.stem}.json and {self.stem}.svg; an existing file is never replaced "
                "(a number is added instead). Escape cancels.",
                markup=False,
            )
        yield KeyFooter()

    def on_input_submitted(self, message: Input.Submitted) -> None:
        """Export into the typed folder."""
        self.dismiss(message.value.strip() or ".")

    def action_cancel(self) -> None:
        """Close without exporting."""
        self.dismiss(None)
