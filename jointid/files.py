"""Every file the program reads is opened here, and every file it writes is written here.

Reading (`open_for_reading`, `check_readable`): only regular files are read. A
FIFO would block the open (or the read) forever and a device can act on being
opened or fill memory (/dev/zero), so both are refused, in one line, before
anything is read; the check is made on what was actually opened, so a FIFO
swapped in after a first look cannot hang the program either. Third-party
readers that open a path themselves (rosbags, sqlite) are handed it only after
`check_readable`.

Writing: atomically, alone or as a group, and never over an existing file unless asked.

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

Even with `overwrite`, only a regular file is ever replaced: a destination that
is a symlink, a directory, a FIFO, a device or a socket is refused (replacing
/dev/null with a regular file would break the system for everyone).

A process killed outright (`kill -9`) cannot remove its temporary files. The
temporaries are named `.jointid.PID-TOKEN-MEMBER.jointid-part`, one TOKEN per
group: short, whatever the final name's length (a legal 254-character name
must stay writable), and free of it. The next write into the same folder
removes those whose process no longer runs, and, for a group that was killed
between the links of its members (the explorer's JSON and SVG pair: a member
whose temporary has no second link was never placed), also the members already
linked into place (the files of the folder that are the same file as their
temporary), so a group never stays half there.

Confined reading (`confine_reading`): a session of `jointid serve` reads only
inside its --data folder. Every read there opens the path from the folder's
own descriptor one component at a time, following no symbolic link
(O_NOFOLLOW through `dir_fd`), and checks the file it opened (fstat against
the lstat it looked at before opening). A path that was checked, then had a
folder swapped for a link out before the read, is refused, never read.

Paths in messages go through `shown_path`, so that a name holding a newline
or another control character still makes a one-line message.
"""

from __future__ import annotations

import errno
import json
import os
import re
import secrets
import stat
from collections import defaultdict
from contextlib import contextmanager
from typing import BinaryIO, Iterator, Sequence, TextIO

from .text_safety import shown_name

TEMPORARY_SUFFIX = ".jointid-part"
"""Ending of every temporary file this module creates (and the only ones it ever removes)."""
TEMPORARY_PATTERN = re.compile(r"^\.jointid\.(?P<pid>[1-9]\d{0,9})-(?P<token>[0-9a-f]{8})-(?P<member>\d{1,6})"
                               + re.escape(TEMPORARY_SUFFIX) + "$")
"""A temporary of this module's naming: the id of the process that created it (at most 10 digits, so a stray name
cannot hold a number os.kill overflows on), its group's token, its place in the group."""
NEW_FILE_MODE = 0o666
"""Mode asked for when creating a file; the umask takes away from it, as for `open(..., "w")`."""


# Paths in messages --------------------------------------------------------------------------------


def shown_path(path) -> str:
    """A path as messages show it: escaped as every name is (`text_safety.shown_name`), so a newline cannot break
    a one-line message in two and what is shown can be typed back (`typed_name`).

    >>> shown_path("logs/run 1.csv"), shown_path("a\\nb.csv"), shown_path(b"caf\\xe9.csv")
    ('logs/run 1.csv', 'a\\\\nb.csv', 'caf\\\\xe9.csv')
    """
    return shown_name(os.fsdecode(path) if isinstance(path, bytes) else str(os.fspath(path)))


def shown_command(words) -> str:
    """A command line as shown: each word escaped as every name is (`text_safety.shown_name`: a raw ESC in a file
    name would drive the terminal that shows the line), then quoted for a shell.

    >>> shown_command(["jointid", "fit", "--csv", "run 1.csv"]), shown_command(["--out", "a\\x1bb"])
    ("jointid fit --csv 'run 1.csv'", "--out 'a\\\\x1bb'")
    """
    import shlex

    from .text_safety import shown_name

    return " ".join(shlex.quote(shown_name(str(word))) for word in words)


def file_kind(mode: int) -> str | None:
    """None for a regular file, else what a `stat` mode is: 'a directory', 'a named pipe (FIFO)', ..."""
    if stat.S_ISREG(mode):
        return None
    kinds = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a named pipe (FIFO)"), (stat.S_ISLNK, "a symbolic link"),
             (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))
    return next((name for test, name in kinds if test(mode)), "a special file")


# Reading ----------------------------------------------------------------------------------------------


class FileRefused(ValueError):
    """A path that cannot be read, or is not a regular file; str() is one line naming it.

    Attributes:
        path: The path as given.
        reason: Why, e.g. 'No such file or directory' or 'a named pipe (FIFO), not a regular file'.
        problem: The message after the path: 'cannot open: <reason>' or 'cannot read: <reason>'.
    """

    def __init__(self, path, verb: str, reason: str):
        self.path, self.reason = os.fspath(path), reason
        self.problem = f"{verb}: {reason}"
        super().__init__(f"{shown_path(self.path)}: {self.problem}")


_READ_FOLDER: str | None = None
"""The only folder this process may read in (a session of `jointid serve --data DIR`), or None for anywhere."""

OPEN_FLAGS = (os.O_RDONLY | getattr(os, "O_BINARY", 0) | getattr(os, "O_CLOEXEC", 0))
"""Flags of every open for reading; each open adds its own."""


def confine_reading(folder: str | os.PathLike | None) -> None:
    """From now on read only inside `folder` (an absolute path without symbolic links), or anywhere again (None)."""
    global _READ_FOLDER
    _READ_FOLDER = None if folder is None else os.fspath(folder)


def _components_within(folder: str, path) -> list[str]:
    """The names leading from `folder` to `path` (absolute, or relative to `folder`); FileRefused when it lies
    outside, or names `..` or `.` on the way."""
    text = os.fsdecode(os.fspath(path))
    relative = os.path.relpath(text, folder) if os.path.isabs(text) else text
    parts = [part for part in relative.split(os.sep) if part]
    if not parts or any(part in (os.curdir, os.pardir) for part in parts):
        raise FileRefused(path, "cannot open", "outside the folder this server may read")
    return parts


def _open_within(folder: str, path) -> int:
    """A descriptor of the regular file at `path` in `folder`, opened from the folder's descriptor one name at a
    time without following any link, and checked to be the file looked at (see the module's docstring)."""
    parts = _components_within(folder, path)
    current = os.open(folder, OPEN_FLAGS | os.O_DIRECTORY)
    try:
        for name in parts[:-1]:
            following = os.open(name, OPEN_FLAGS | os.O_DIRECTORY | os.O_NOFOLLOW, dir_fd=current)
            os.close(current)
            current = following
        looked = os.stat(parts[-1], dir_fd=current, follow_symlinks=False)
        kind = file_kind(looked.st_mode)
        if kind is not None:  # not opened: a FIFO would wait, a device can act on being opened
            raise FileRefused(path, "cannot read", f"{kind}, not a regular file")
        before_open_hook()
        descriptor = os.open(parts[-1], OPEN_FLAGS | os.O_NOFOLLOW | getattr(os, "O_NONBLOCK", 0), dir_fd=current)
        opened = os.fstat(descriptor)
        if (opened.st_dev, opened.st_ino) != (looked.st_dev, looked.st_ino) or file_kind(opened.st_mode):
            os.close(descriptor)
            raise FileRefused(path, "cannot open", "it changed while it was being opened")
        return descriptor
    except OSError as error:
        if error.errno in (errno.ELOOP, errno.ENOTDIR):  # O_NOFOLLOW met a link (or a file where a folder was)
            raise FileRefused(path, "cannot open", "a symbolic link or a file on its way; only what lies in "
                              "the folder this server may read is read") from None
        raise
    finally:
        os.close(current)


def before_open_hook() -> None:
    """Called between looking at a file and opening it: nothing, except in the test that swaps the file there."""


def open_for_reading(path) -> BinaryIO:
    """The regular file at `path`, opened for binary reading; FileRefused for anything else or any error.

    Under `confine_reading` the path is opened from the folder without following links (`_open_within`).

    Raises:
        FileRefused: "cannot open: <reason>" when the path cannot be opened, or "cannot read: a named pipe
            (FIFO), not a regular file" (a directory, a device, a socket...) without opening it.
    """
    if _READ_FOLDER is not None:
        try:
            return os.fdopen(_open_within(_READ_FOLDER, path), "rb")
        except FileRefused:
            raise
        except (OSError, ValueError) as error:
            raise FileRefused(path, "cannot open", _reason(error)) from None
    try:
        # Looked at before opening: opening a FIFO waits for a writer, and opening a device can act on it.
        kind = file_kind(os.stat(path).st_mode)
        if kind is None:
            # Non-blocking, so that a FIFO swapped in since the stat cannot hang the open; fstat checks what was
            # actually opened. (The flag changes nothing for regular files.)
            descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0)
                                 | getattr(os, "O_CLOEXEC", 0))
            kind = file_kind(os.fstat(descriptor).st_mode)
            if kind is None:
                return os.fdopen(descriptor, "rb")
            os.close(descriptor)
    except (OSError, ValueError) as error:  # ValueError: a NUL byte in the path
        raise FileRefused(path, "cannot open", _reason(error)) from None
    raise FileRefused(path, "cannot read", f"{kind}, not a regular file")


def check_readable(path) -> None:
    """FileRefused unless `path` is a regular file that can be opened, for readers that open the path themselves."""
    open_for_reading(path).close()


def read_bytes(path, limit: int) -> bytes:
    """Up to `limit` + 1 bytes of the regular file at `path` (one more than `limit` says it is larger); FileRefused
    as `open_for_reading`, or "cannot read: <reason>"."""
    with open_for_reading(path) as handle:
        try:
            return handle.read(limit + 1)
        except OSError as error:
            raise FileRefused(path, "cannot read", _reason(error)) from None


# Writing ----------------------------------------------------------------------------------------------


class ExportError(OSError):
    """A file could not be written; str() is one line naming the file."""


class AlreadyExists(ExportError):
    """The destination name is taken, and `overwrite` was not given."""


class NotRegularFile(ExportError):
    """The destination is a symlink, a directory, a FIFO, a device or a socket, which are never replaced."""


def temporary_path(path: str, token: str | None = None, member: int = 0) -> str:
    """A temporary name beside `path`, carrying this process's id (so a later run can tell it is stale), the
    group's `token` (fresh when None) and the `member`'s place in it; never longer than 45 characters."""
    folder = os.path.dirname(path)
    token = secrets.token_hex(4) if token is None else token
    return os.path.join(folder, f".jointid.{os.getpid()}-{token}-{member}{TEMPORARY_SUFFIX}")


def _process_exists(pid: int) -> bool:
    """Whether process `pid` may still run (True when we cannot tell, so its file is left alone)."""
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)  # signal 0: only asks whether the process exists
    except ProcessLookupError:
        return False
    except (OSError, OverflowError, ValueError):  # someone else's, or no pid this system has: leave it alone
        return True
    return True


def remove_stale_temporaries(folder: str) -> list[str]:
    """Remove temporaries of this module's naming in `folder` whose writing process is gone; their paths.

    A group killed between the links of its members (some final name still free) is finished the only safe way,
    by removing the members already linked into place, recognised as still the same file as their temporary;
    a group whose every final name is taken is left as it is. The removed finals are among the paths returned.
    """
    removed = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed  # cannot list the folder: the write itself will say why
    groups = defaultdict(list)  # (pid, token) -> [(temporary, its stat)]
    for entry in entries:
        match = TEMPORARY_PATTERN.match(entry.name)
        if match is None or _process_exists(int(match["pid"])):
            continue
        try:
            groups[match["pid"], match["token"]].append((entry.path, entry.stat(follow_symlinks=False)))
        except OSError:
            continue  # removed meanwhile by another run
    for members in groups.values():
        unwanted = [temporary for temporary, _ in members]
        if any(found.st_nlink < 2 for _, found in members):  # killed before linking them all
            unwanted += _linked_finals(entries, members)
        for path in unwanted:
            try:
                os.unlink(path)
                removed.append(path)
            except OSError:
                pass  # another run removed it first, or we may not: it is only litter
    return removed


def _linked_finals(entries: list, members: list) -> list[str]:
    """The files of the folder (`entries`) that are the same file as one of the temporaries `members` under
    another name: the members a killed group had already linked into place."""
    inodes = {(found.st_dev, found.st_ino) for _, found in members if found.st_nlink > 1}
    temporaries = {temporary for temporary, _ in members}
    finals = []
    for entry in entries:
        if entry.path in temporaries or not inodes:
            continue
        try:
            found = entry.stat(follow_symlinks=False)
        except OSError:
            continue
        if (found.st_dev, found.st_ino) in inodes:
            finals.append(entry.path)
    return finals


def refuse_special_destination(path: str) -> None:
    """NotRegularFile when `path` names anything but a regular file or nothing (a symlink is not followed)."""
    try:
        kind = file_kind(os.lstat(path).st_mode)
    except FileNotFoundError:
        return
    except (OSError, ValueError) as error:  # e.g. a name too long, a folder we may not look into, a NUL byte
        raise ExportError(f"{shown_path(path)}: cannot write: {_reason(error)}") from None
    if kind is not None:
        raise NotRegularFile(f"{shown_path(path)}: {kind}, not a regular file; not replacing it")


def _reason(error: OSError) -> str:
    """An OSError's reason without the file name or errno number, e.g. 'No space left on device'."""
    return getattr(error, "strerror", None) or str(error) or type(error).__name__


def _open_temporary(path: str, token: str, member: int) -> tuple[str, TextIO]:
    """Create a new temporary file for `path`, the `member`-th of the group `token` (mode from the umask), and
    open it as UTF-8 text."""
    temporary = temporary_path(path, token, member)
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
        refuse_special_destination(path)  # looked at again just before: one may have appeared while writing
        os.replace(temporary, path)
        return
    try:
        os.link(temporary, path)  # atomic and fails with FileExistsError if the name is taken
    except FileExistsError:
        raise _already_exists(path) from None
    except OSError:  # no hard links here (some file systems): check, then rename
        if os.path.lexists(path):
            raise _already_exists(path) from None
        os.replace(temporary, path)


def _already_exists(path: str) -> AlreadyExists:
    return AlreadyExists(f"{shown_path(path)}: already exists; not overwriting it")


@contextmanager
def atomic_outputs(paths: Sequence, *, overwrite: bool = False) -> Iterator[list[TextIO]]:
    """Yield one text file per path; they appear at their paths together when the block finishes, or none does.

    Raises:
        NotRegularFile: A path names a symlink, a directory, a FIFO, a device or a socket (nothing written),
            `overwrite` or not.
        AlreadyExists: A path is taken and `overwrite` is false (nothing written).
        ExportError: Any operating-system error while creating, writing or renaming (nothing left behind).
    """
    paths = [os.fspath(path) for path in paths]
    for path in paths:
        refuse_special_destination(path)
        if not overwrite and os.path.lexists(path):
            raise _already_exists(path)
    token = secrets.token_hex(4)  # one for the group, so a later run can tell its members belong together
    try:
        folders = dict.fromkeys(os.path.dirname(os.path.abspath(path)) for path in paths)
    except OSError as error:  # a relative path while the current folder has been removed
        raise ExportError(f"{', '.join(map(shown_path, paths))}: cannot write: {_reason(error)}") from None
    for folder in folders:
        remove_stale_temporaries(folder)
    temporaries: list[str] = []
    handles: list[TextIO] = []
    placed: list[str] = []
    done = False
    try:
        for member, path in enumerate(paths):
            temporary, handle = _open_temporary(path, token, member)
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
        raise ExportError(f"{', '.join(map(shown_path, paths))}: cannot write: {_reason(error)}") from None
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
