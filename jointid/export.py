"""Write files atomically and never over an existing file unless asked.

A reader (or a crash) never sees a half-written file: the content goes to a
temporary file in the destination's folder, is flushed to disk, and is then
renamed into place in one step. Without `overwrite`, the final step is a hard
link, which fails if the destination exists, so a file that appears between
the check and the rename is not clobbered either.
"""

from __future__ import annotations

import json
import os
import tempfile
from contextlib import contextmanager
from typing import Iterator, TextIO


class ExportError(OSError):
    """A file could not be written; str() is one line naming the file."""


@contextmanager
def atomic_output(path, *, overwrite: bool = False) -> Iterator[TextIO]:
    """Yield a text file whose content appears at `path` only if the block finishes without error."""
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    if not overwrite and os.path.lexists(path):
        raise ExportError(f"{path}: already exists; not overwriting it")
    try:
        handle = tempfile.NamedTemporaryFile(
            "w", dir=folder, prefix=f".{os.path.basename(path)}.", suffix=".tmp",
            delete=False, encoding="utf-8", newline="\n",
        )
    except OSError as error:
        raise ExportError(f"{path}: cannot write: {error.strerror or error}") from None
    committed = False
    try:
        with handle:
            yield handle
            handle.flush()
            os.fsync(handle.fileno())
        _commit(handle.name, path, overwrite)
        committed = True
    finally:
        if not committed:
            try:
                os.unlink(handle.name)
            except FileNotFoundError:
                pass


def _commit(temporary: str, path: str, overwrite: bool) -> None:
    """Move the finished temporary file to `path` (refusing to replace one unless `overwrite`)."""
    try:
        if overwrite:
            os.replace(temporary, path)
            return
        try:
            os.link(temporary, path)  # atomic and fails with FileExistsError if path exists
        except FileExistsError:
            raise ExportError(f"{path}: already exists; not overwriting it") from None
        except OSError:  # no hard links here (some file systems): check, then rename
            if os.path.lexists(path):
                raise ExportError(f"{path}: already exists; not overwriting it") from None
            os.replace(temporary, path)
            return
        os.unlink(temporary)
    except ExportError:
        raise
    except OSError as error:
        raise ExportError(f"{path}: cannot write: {error.strerror or error}") from None


def write_text(path, text: str, *, overwrite: bool = False) -> None:
    """Write `text` to `path` atomically; ExportError if it exists (unless `overwrite`) or cannot be written."""
    with atomic_output(path, overwrite=overwrite) as handle:
        handle.write(text)


def write_json(path, document, *, overwrite: bool = False) -> None:
    """Write a JSON document (indented, UTF-8, final newline) to `path` atomically."""
    write_text(path, json.dumps(document, indent=2, ensure_ascii=False) + "\n", overwrite=overwrite)
