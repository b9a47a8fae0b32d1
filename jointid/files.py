"""Write files atomically, alone or as a group, and never over an existing file unless asked.

A reader (or a crash) never sees a half-written file: each file's content goes
to a temporary file in its destination's folder, is flushed to disk, and only
then is renamed into place. A group (the explorer's JSON and SVG pair) is
renamed only once every member is written, so a failure leaves none of them.
Without `overwrite`, the final step is a hard link, which fails if the
destination exists, so a file that appears between the check and the rename
is not clobbered either; a name that is taken by anything, a dangling symlink
included, counts as existing.

Every operating-system error (a full disk, a read-only or missing folder) is
turned into one `ExportError` whose text is one line, after whatever was
written has been removed. New files get the mode the umask gives (as `open`
would), not the 0600 of `tempfile`.

A process killed outright (`kill -9`) cannot remove its temporary file. The
temporaries are named `.NAME.PID-TOKEN.jointid-part`; the next write into the
same folder removes those whose process no longer runs.
"""

from __future__ import annotations

import json
import os
import re
import secrets
from contextlib import contextmanager
from typing import Iterator, Sequence, TextIO

TEMPORARY_SUFFIX = ".jointid-part"
"""Ending of every temporary file this module creates (and the only ones it ever removes)."""
TEMPORARY_PATTERN = re.compile(r"^\..+\.(\d+)-[0-9a-f]{8}" + re.escape(TEMPORARY_SUFFIX) + "$")
"""A temporary of this module's naming; group 1 is the process id that created it."""
NEW_FILE_MODE = 0o666
"""Mode asked for when creating a file; the umask takes away from it, as for `open(..., "w")`."""


class ExportError(OSError):
    """A file could not be written; str() is one line naming the file."""


class AlreadyExists(ExportError):
    """The destination name is taken, and `overwrite` was not given."""


def temporary_path(path: str) -> str:
    """A fresh temporary name beside `path`, carrying this process's id so a later run can tell it is stale."""
    folder, name = os.path.split(path)
    return os.path.join(folder, f".{name}.{os.getpid()}-{secrets.token_hex(4)}{TEMPORARY_SUFFIX}")


def _process_exists(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)  # signal 0: only asks whether the process exists
    except ProcessLookupError:
        return False
    except OSError:  # it exists but belongs to someone else, or we cannot tell: leave its file alone
        return True
    return True


def remove_stale_temporaries(folder: str) -> list[str]:
    """Remove temporaries of this module's naming in `folder` whose writing process is gone; their paths."""
    removed = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed  # cannot list the folder: the write itself will say why
    for entry in entries:
        match = TEMPORARY_PATTERN.match(entry.name)
        if match is None or _process_exists(int(match.group(1))):
            continue
        try:
            os.unlink(entry.path)
            removed.append(entry.path)
        except OSError:
            pass  # another run removed it first, or we may not: it is only litter
    return removed


def _reason(error: OSError) -> str:
    """An OSError's reason without the file name or errno number, e.g. 'No space left on device'."""
    return error.strerror or str(error) or type(error).__name__


def _open_temporary(path: str) -> tuple[str, TextIO]:
    """Create a new temporary file for `path` (mode from the umask) and open it as UTF-8 text."""
    temporary = temporary_path(path)
    descriptor = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0),
                         NEW_FILE_MODE)
    try:
        return temporary, os.fdopen(descriptor, "w", encoding="utf-8", newline="\n")
    except BaseException:
        os.close(descriptor)
        os.unlink(temporary)
        raise


def _link_into_place(temporary: str, path: str, overwrite: bool) -> None:
    """Give the finished temporary file its final name (refusing a taken one unless `overwrite`)."""
    if overwrite:
        os.replace(temporary, path)
        return
    try:
        os.link(temporary, path)  # atomic and fails with FileExistsError if the name is taken
    except FileExistsError:
        raise AlreadyExists(f"{path}: already exists; not overwriting it") from None
    except OSError:  # no hard links here (some file systems): check, then rename
        if os.path.lexists(path):
            raise AlreadyExists(f"{path}: already exists; not overwriting it") from None
        os.replace(temporary, path)


@contextmanager
def atomic_outputs(paths: Sequence, *, overwrite: bool = False) -> Iterator[list[TextIO]]:
    """Yield one text file per path; they appear at their paths together when the block finishes, or none does.

    Raises:
        AlreadyExists: A path is taken and `overwrite` is false (nothing written).
        ExportError: Any operating-system error while creating, writing or renaming (nothing left behind).
    """
    paths = [os.fspath(path) for path in paths]
    if not overwrite:
        for path in paths:
            if os.path.lexists(path):
                raise AlreadyExists(f"{path}: already exists; not overwriting it")
    for folder in dict.fromkeys(os.path.dirname(os.path.abspath(path)) for path in paths):
        remove_stale_temporaries(folder)
    temporaries: list[str] = []
    handles: list[TextIO] = []
    placed: list[str] = []
    done = False
    try:
        for path in paths:
            temporary, handle = _open_temporary(path)
            temporaries.append(temporary)
            handles.append(handle)
        yield handles
        for handle in handles:  # a full disk may only show here, when the buffer is written out
            handle.flush()
            os.fsync(handle.fileno())
            handle.close()
        for temporary, path in zip(temporaries, paths):
            _link_into_place(temporary, path, overwrite)
            placed.append(path)
        done = True
    except ExportError:
        raise
    except OSError as error:
        raise ExportError(f"{', '.join(paths)}: cannot write: {_reason(error)}") from None
    finally:
        for handle in handles:
            try:
                handle.close()
            except OSError:
                pass  # closing flushes; the disk is full: the file is removed just below anyway
        for temporary in temporaries:
            try:
                os.unlink(temporary)  # after a link the final name keeps the content
            except FileNotFoundError:
                pass  # renamed into place (no hard links) or never created
            except OSError:
                pass
        if not done and not overwrite:
            for path in placed:  # keep the group together: none without the others
                try:
                    os.unlink(path)
                except OSError:
                    pass


@contextmanager
def atomic_output(path, *, overwrite: bool = False) -> Iterator[TextIO]:
    """Yield a text file whose content appears at `path` only if the block finishes without error.

    Raises:
        AlreadyExists: `path` is taken and `overwrite` is false.
        ExportError: Any operating-system error, with nothing left behind.
    """
    with atomic_outputs([path], overwrite=overwrite) as (handle,):
        yield handle


def write_texts(texts: dict, *, overwrite: bool = False) -> None:
    """Write several files ({path: text}) atomically as a group: all of them or none."""
    with atomic_outputs(list(texts), overwrite=overwrite) as handles:
        for handle, text in zip(handles, texts.values()):
            handle.write(text)


def write_text(path, text: str, *, overwrite: bool = False) -> None:
    """Write `text` to `path` atomically; ExportError if it exists (unless `overwrite`) or cannot be written."""
    write_texts({path: text}, overwrite=overwrite)


def json_text(document) -> str:
    """A JSON document as written: indented, UTF-8 characters kept, final newline."""
    return json.dumps(document, indent=2, ensure_ascii=False) + "\n"


def write_json(path, document, *, overwrite: bool = False) -> None:
    """Write a JSON document (indented, UTF-8, final newline) to `path` atomically."""
    write_text(path, json_text(document), overwrite=overwrite)
