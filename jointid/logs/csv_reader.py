"""Read a joint log from CSV: t, q, qd, qdd, tau by header name, checked row by row.

Format: comma-separated, one header row, then one sample per row. Lines whose
first non-blank character is `#` are comments wherever they stand; blank lines
are skipped too. Columns are found by name, case-insensitively and in any order:
t (s), q (rad), qd (rad/s), qdd (rad/s^2) and tau (N m), or the names
loggers give them (time, position, velocity, acceleration, torque, effort...;
see jointid.logs.conventions), or as a column map names them. Other columns are
ignored (their cells need not be numbers) but every row must have as many cells
as the header. Cells are not quoted.

Rows in messages are 1-based line numbers in the file, so an editor's "go to
line" finds them; columns are 1-based positions with their header name.

Only regular files are read (jointid.files.open_for_reading): a FIFO would block
the open forever and /dev/zero would fill memory, so both are refused before anything is read. A
line running on past MAX_LINE_BYTES is refused as soon as reading has to hold
it whole (the header, or a data line that does not fit in one chunk), so no
single line costs more memory than a chunk plus MAX_LINE_BYTES.

Checks: every recognised cell a finite number; t, when present, never running
backwards and never repeating with other values (jointid.logs.timing). Only when qd
or qdd must be estimated does the differentiator need uniform sampling: jittered
steps are then resampled onto a uniform grid and gaps refused (jointid.logs.timing);
a log with both derivatives keeps its timestamps as recorded.

Speed: without a progress callback or a cancel check (the command line), the
data go to pandas' C reader in one call given the file's path, its fastest way:
close to `pandas.read_csv(path)` itself. A screen of the bytes, run in a thread
beside pandas' (_screen_rest), and checks of what it returns keep that call from accepting
anything the checked reading below would not; on any doubt the file is read
that way instead, which then names the problem or reads the same doubles.

Otherwise (the explorer, with progress and cancel), the file is read in chunks
of CHUNK_BYTES, so memory stays near the size of the numbers rather than of
the text, and a caller can follow progress and cancel between chunks. Each
chunk is parsed by pandas' C reader (imported lazily, on the first load: it is
about 5x faster than numpy.loadtxt), but only
when the chunk has none of the text on which fuzzing the two readers against
each other found them to differ (see _FAST_UNSAFE). Otherwise, or when pandas
rejects anything, the chunk goes to numpy.loadtxt exactly as before, and only
when that fails too is it scanned line by line in Python, to say exactly which
cell is wrong. Both readers round every number correctly (pandas from 3.1), so
values are float() of the text.
"""

from __future__ import annotations

import csv
import io
import os
import re
import threading
import warnings

import numpy as np

from ..files import FileRefused, open_for_reading
from ..norms import all_finite
from ..options import DEFAULT_ORDER, DEFAULT_WINDOW
from .derivatives import check_filter
from .pipeline import JointLog, check_finite, joint_log_from_table
from .conventions import ColumnMap, ColumnProblem, columns_note, match_columns, read_as, suggested_map
from .table import (
    CHUNK_BYTES,
    COLUMNS,
    CancelCheck,
    LoadCancelled,
    LogError,
    LogTable,
    ProgressCallback,
    count_newlines,
)

MAX_LINE_BYTES = 1 << 20
"""Longest line reading will hold whole (1 MiB, tens of thousands of columns): a file with no newline in
its first megabyte is not a log of one sample per line, and reading on would hold all of it in memory.
Shorter data lines are always read; longer ones inside a chunk are left to the row checks."""

_PLAIN = b"0123456789.eE+-,\n"
"""Bytes of plain numeric text: a chunk of only these needs no further look before pandas reads it."""

_FAST_UNSAFE = b" \t\v\f\x00aAuU"
"""Bytes that keep a chunk from pandas' reader, which accepts cells numpy.loadtxt rejects:
whitespace inside a number ('3e 2' is 300 to pandas), and true/false in any case (as 1/0;
every spelling has an a or a u, and the numbers 'inf' and 'infinity' have neither).
Found by fuzzing the two readers against each other; see tests/core/logs/test_csv_reader.py."""

# ASCII: to re, "٣" is a digit (\d), but neither reader takes it as one.
_NUMBER = re.compile(r"[+-]?(\d+\.?\d*([eE][+-]?\d+)?|\.\d+([eE][+-]?\d+)?|nan|inf|infinity)", re.I | re.ASCII)


def read_table(
    path,
    *,
    progress: ProgressCallback | None = None,
    cancel: CancelCheck | None = None,
    chunk_bytes: int = CHUNK_BYTES,
    column_map: ColumnMap | None = None,
) -> LogTable:
    """Read and check the header and every row of a CSV log; raise LogError on the first problem.

    Columns are found by name (conventions.match_columns): t, q, qd, qdd, tau, the names loggers use for
    them, or as `column_map` names them.

    With neither `progress` nor `cancel` and the default `chunk_bytes`, pandas reads the whole file in one
    call when it can (see the module's notes); otherwise, and for any file it might read differently, the
    data are read in chunks of `chunk_bytes`.
    """
    path = os.fspath(path)
    handle = _open_regular_file(path)
    try:
        with handle:
            total = os.fstat(handle.fileno()).st_size
            reader = _ChunkReader(path, handle, total, progress, cancel, chunk_bytes, column_map)
            return reader.read()
    except OSError as error:  # e.g. a directory, or a read error mid-file
        raise LogError(path, f"cannot read: {error.strerror or error}") from None


def _open_regular_file(path: str):
    """The file opened for binary reading (jointid.files.open_for_reading); LogError if it cannot be, or if it is not
    a regular file."""
    if not str(path).strip():
        raise LogError("(no file)", "cannot open: the path is empty; give a CSV file's path")
    try:
        return open_for_reading(path)
    except FileRefused as error:
        raise LogError(path, error.problem) from None


class _ChunkReader:
    """Reads one open log: header first, then data in newline-aligned chunks.

    Clean chunks are not even scanned for line numbers: lines are only counted
    (by rereading the file) when a message needs one.
    """

    def __init__(self, path, handle, total, progress, cancel, chunk_bytes, column_map=None):
        self.path, self.handle, self.total, self.column_map = path, handle, total, column_map
        self.progress, self.cancel, self.chunk_bytes = progress, cancel, max(int(chunk_bytes), 1)
        self.whole_file_allowed = progress is None and cancel is None and chunk_bytes == CHUNK_BYTES

    def read(self) -> LogTable:
        header_line, names = self._read_header()
        positions = _check_header(self.path, header_line, names, self.column_map)
        wanted = tuple(n for n in COLUMNS if n in positions)
        named = read_as(names, {key: position - 1 for key, position in positions.items()})
        note = columns_note(named)
        described = dict(read_as=named, notes=() if note is None else (note,))
        self.width = len(names)
        # Without extra columns loadtxt parses every cell and checks row widths itself;
        # the columns are then put in COLUMNS order if the file has another order.
        file_order = [positions[n] - 1 for n in wanted]
        # pandas returns the used columns in file order; with usecols, loadtxt returns them in COLUMNS order.
        self.fast_cols = sorted(file_order)
        self.fast_order = [self.fast_cols.index(c) for c in file_order]
        self.usecols = None if len(wanted) == self.width else tuple(file_order)
        self.order = file_order if self.usecols is None and file_order != sorted(file_order) else None
        self.wanted, self.positions, self.names = wanted, positions, names
        ignored = tuple(
            n or f"(unnamed column {i + 1})" for i, n in enumerate(names) if i + 1 not in positions.values()
        )
        whole = self._whole_file(file_order, header_line) if self.whole_file_allowed else None
        if whole is not None:
            columns, offset = whole
            return LogTable(path=self.path, columns=dict(zip(wanted, columns)),
                            positions={n: positions[n] for n in wanted}, ignored=ignored, segments=((0, offset),),
                            **described)
        store = _ColumnStore(len(wanted), self.total)
        segments = []
        while True:
            if self.cancel is not None and self.cancel():
                raise LoadCancelled(self.path)
            offset, data = self._next_chunk()
            if not data:
                break
            values = self._parse(data, offset)
            if self.order is not None:
                values = values[:, self.order]
            if len(values):
                segments.append((store.rows, offset))
                store.append(values, len(data))
            if self.progress is not None:
                self.progress(offset + len(data), self.total)
        if store.rows == 0:
            raise LogError(self.path, "has a header but no data rows", header_line)
        table = LogTable(
            path=self.path,
            columns=dict(zip(wanted, store.columns())),
            positions={n: positions[n] for n in wanted},
            ignored=ignored,
            segments=tuple(segments),
            **described,
        )
        check_finite(table)
        return table

    def _whole_file(self, file_order: list[int], header_line: int) -> tuple[list[np.ndarray], int] | None:
        """(the wanted columns, the data's byte offset) read by pandas in one call from the file's path, or
        None (and the file position unchanged) when that cannot be done or might differ from the chunked
        reading, which then names the problem or reads the same doubles.

        pandas is handed a path, not our handle: it reads a path about twice as fast. The path is
        /proc/self/fd/N, the file this handle has open, so a file swapped in since the regular-file check
        (a FIFO would block) is never read; without /proc the chunked reading is used. Every cell is parsed
        as a number, ignored columns too (a file whose ignored columns hold text goes the chunked way, which
        skips them). pandas refuses a row with too few cells (an empty cell is not a number) and, with its
        warnings raised, one with too many; _screen_rest first refuses the bytes on which pandas might read
        a number loadtxt would not; a value that is not finite goes back for its message.
        """
        read_csv = _pandas_read_csv()
        own_file = f"/proc/self/fd/{self.handle.fileno()}"
        if read_csv is None or not os.path.exists(own_file):
            return None
        start = self.handle.tell()
        # The screen runs beside pandas' reading, which parses in threads that leave the GIL: its result
        # only decides whether pandas' frame is used (about a fifth of the load's time saved).
        screen = _ScreenThread(self.handle.fileno(), start)
        screen.start()
        try:
            first = self.handle.readline(MAX_LINE_BYTES + 1)
            with warnings.catch_warnings():
                warnings.simplefilter("error")  # a first row with an extra cell is only a ParserWarning
                frame = read_csv(
                    own_file,
                    engine="c",
                    header=None,
                    skiprows=header_line,
                    names=range(self.width),
                    index_col=False,
                    dtype=np.float64,
                    na_filter=False,  # "NA", "" and the like are not numbers here
                    quoting=csv.QUOTE_NONE,
                    comment=None,  # a comment line is no row of numbers: it goes the chunked way
                    skip_blank_lines=True,
                    # The default UTF-8, unlike latin-1, hands the bytes on undecoded (latin-1 cost a sixth
                    # more time); a byte that is not UTF-8 is no number, and such a cell is refused anyway.
                )
            columns = [frame[index].to_numpy(dtype=np.float64) for index in file_order]
            # pandas counted the lines it skipped itself: its first row must be the line after the header.
            agrees = len(columns[0]) > 0 and [float(cell) for cell in first.split(b",")] == [
                float(value) for value in frame.iloc[0]
            ]
        except Exception:  # any refusal: the chunked reading decides what it was
            agrees = False
        finally:
            screen.join()
            self.handle.seek(start)
        if not screen.passed or not agrees or not all(all_finite(column) for column in columns):
            return None  # the chunked reading names the row and column of a value that is not finite
        return columns, start

    def _read_header(self) -> tuple[int, list[str]]:
        """Skip leading comments and blank lines; return the header's line number and names."""
        line = 0
        while True:
            raw = self.handle.readline(MAX_LINE_BYTES + 1)
            if not raw:
                raise LogError(self.path, "is empty: no header row")
            line += 1
            if len(raw) > MAX_LINE_BYTES:
                raise _long_line(self.path, line)
            if line == 1 and raw.startswith(b"\xef\xbb\xbf"):  # a UTF-8 byte order mark
                raw = raw[3:]
            if b"\x00" in raw:  # UTF-8 and ASCII text never hold a NUL byte; UTF-16 text is full of them
                raise LogError(
                    self.path, "holds NUL bytes: binary data or UTF-16/32 text; save it as UTF-8 or ASCII text", line
                )
            text = raw.decode("utf-8", errors="replace").strip()
            if text and not text.startswith("#"):
                return line, [cell.strip().strip('"').strip() for cell in text.split(",")]

    def _next_chunk(self) -> tuple[int, bytes]:
        """(offset, bytes) of the next run of whole lines, about chunk_bytes long; b"" at the end."""
        offset = self.handle.tell()
        data = self.handle.read(self.chunk_bytes)
        while len(data) >= self.chunk_bytes and not data.endswith(b"\n"):
            cut = data.rfind(b"\n") + 1
            if cut:  # give back the partial last line; the next chunk starts with it
                self.handle.seek(offset + cut)
                return offset, data[:cut]
            if len(data) > MAX_LINE_BYTES:  # no newline yet: refuse before holding the whole line
                raise _long_line(self.path, count_newlines(self.path, offset) + 1)
            more = self.handle.read(self.chunk_bytes)  # one line longer than a chunk
            if not more:
                break
            data += more
        return offset, data

    def _parse(self, data: bytes, offset: int) -> np.ndarray:
        """(rows, wanted) values of one chunk of whole lines starting at byte `offset`."""
        if data.isspace():
            return np.empty((0, len(self.wanted)))
        if b"#" not in data:  # both readers skip empty lines themselves
            values = self._fast(data)
            if values is not None:
                return values
            values = self._loadtxt(data)
            if values is not None and values.shape[1] == len(self.wanted) and self._widths_ok(data):
                return values
        # Comment lines, whitespace-only lines or an error: keep only the data lines.
        kept, relative = [], []
        for number, text in enumerate(data.split(b"\n")):
            stripped = text.strip()
            if stripped and not stripped.startswith(b"#"):
                kept.append(text)
                relative.append(number)
        if not kept:
            return np.empty((0, len(self.wanted)))
        joined = b"\n".join(kept)
        values = self._fast(joined)
        if values is not None:
            return values
        values = self._loadtxt(joined)
        if values is None or values.shape != (len(kept), len(self.wanted)) or not self._widths_ok(joined):
            first_line = count_newlines(self.path, offset) + 1
            self._diagnose(kept, [first_line + r for r in relative])
            raise LogError(self.path, "cannot be read as comma-separated numbers", first_line)
        return values

    def _fast(self, data: bytes) -> np.ndarray | None:
        """pandas' C parser on one chunk, or None when it might disagree with loadtxt or rejects something."""
        read_csv = _pandas_read_csv()
        if read_csv is None:
            return None
        rest = data.translate(None, _PLAIN)  # one fast pass; usually empty
        if rest:
            if len(rest.translate(None, _FAST_UNSAFE)) != len(rest):
                return None
            # A lone carriage return ends a line for both readers but not for the row-width check.
            if b"\r" in rest and data.count(b"\r") != data.count(b"\r\n"):
                return None
        rows = self._data_rows(data)
        if rows is None:
            return None
        try:
            frame = read_csv(
                io.BytesIO(data),
                engine="c",
                header=None,
                names=range(self.width),
                usecols=self.fast_cols,
                index_col=False,
                dtype=np.float64,
                na_filter=False,  # "NA", "" and the like are not numbers here
                quoting=csv.QUOTE_NONE,
                comment=None,  # a '#' is never inside a line that reaches here
                skip_blank_lines=True,
                encoding="latin-1",  # ignored columns need not be UTF-8
            )
            values = frame.to_numpy(dtype=np.float64)
        except Exception:  # any refusal: loadtxt and the diagnosis decide what it was
            return None
        if values.shape != (rows, len(self.wanted)):
            return None
        if self.usecols is not None and self.fast_order != sorted(self.fast_order):
            values = values[:, self.fast_order]
        return values

    def _data_rows(self, data: bytes) -> int | None:
        """Count of non-empty lines when each has exactly as many cells as the header, else None."""
        buffer = np.frombuffer(data, dtype=np.uint8)
        ends = np.flatnonzero(buffer == ord("\n"))
        if not data.endswith(b"\n"):
            ends = np.append(ends, len(buffer))
        commas = np.searchsorted(np.flatnonzero(buffer == ord(",")), ends)
        per_line = np.diff(commas, prepend=0)
        lengths = np.diff(ends, prepend=-1) - 1
        empty = (lengths == 0) | ((lengths == 1) & (buffer[np.maximum(ends - 1, 0)] == ord("\r")))
        if not np.all((per_line == self.width - 1) | empty):
            return None
        return len(ends) - int(np.count_nonzero(empty))

    def _loadtxt(self, data: bytes) -> np.ndarray | None:
        """numpy's C parser on one chunk, or None when it rejects something."""
        try:
            return np.loadtxt(
                io.BytesIO(data), delimiter=",", comments=None, ndmin=2, usecols=self.usecols, dtype=float
            )
        except ValueError:
            return None

    def _widths_ok(self, data: bytes) -> bool:
        """True when every line has as many cells as the header (loadtxt checks this itself without usecols)."""
        return self.usecols is None or self._data_rows(data) is not None

    def _diagnose(self, texts: list[bytes], lines: list[int]) -> None:
        """Find the first bad row in a chunk that failed to parse, and raise LogError for it."""
        names = {self.positions[n] - 1: n for n in self.wanted}
        for text, line in zip(texts, lines):
            cells = text.decode("utf-8", errors="replace").rstrip("\r").split(",")
            if len(cells) != self.width:
                raise LogError(
                    self.path, f"has {len(cells)} cells but the header has {self.width} columns", line
                )
            for index in sorted(names):
                cell = cells[index].strip()
                if not _NUMBER.fullmatch(cell):
                    what = "is empty" if not cell else f"{_shorten(cell)!r} is not a number"
                    header = self.names[index] if self.names[index].lower() != names[index] else names[index]
                    raise LogError(self.path, what, line, f"{index + 1} ({header})")


_DOUBTFUL = tuple(bytes([b]) for b in _FAST_UNSAFE.replace(b"\x00", b""))
"""Bytes that keep a file from pandas' one-call reading: _FAST_UNSAFE but NUL. In that reading every
cell is a number, and pandas refuses one holding a NUL or a '#' (a comment line) itself; each byte value
left out saves a memchr pass over the file."""

_SCREEN_BYTES = 1 << 16
"""Bytes screened at a time: a block stays in cache for its memchr passes, and the buffer, held while
pandas reads, adds little to the load's peak resident set (256 KiB screened a tenth faster)."""


def _screen_rest(descriptor: int, offset: int) -> bool:
    """True when an open file, from byte `offset` on, holds nothing on which pandas' one-call reading might
    differ.

    Doubtful: a byte of _DOUBTFUL (whitespace and true/false can read as numbers to pandas, not to
    loadtxt), a carriage return not followed by a newline (a line end to pandas, not to the row checks)
    and a line longer than MAX_LINE_BYTES (the chunked reading may refuse it). One memchr per doubtful
    byte value per block: about a fifth of pandas' time. Read with pread, which leaves the file's
    position alone (the caller reads from it meanwhile).
    """
    run = 0  # bytes of the current line in earlier blocks
    carriage_return_pending = False  # the last block ended in "\r"
    # One buffer for every block: fresh 256 KiB blocks, freed one after another, left memory behind that
    # raised the load's peak resident set above pandas.read_csv's own.
    buffer = bytearray(_SCREEN_BYTES)
    while True:
        size = os.preadv(descriptor, [buffer], offset)
        offset += size
        if not size:
            return not carriage_return_pending
        if any(buffer.find(byte, 0, size) >= 0 for byte in _DOUBTFUL):
            return False
        if carriage_return_pending and not buffer.startswith(b"\n", 0, size):
            return False
        carriage_return_pending = False
        if buffer.find(b"\r", 0, size) >= 0:
            carriage_return_pending = buffer.endswith(b"\r", 0, size)
            if buffer.count(b"\r", 0, size) - buffer.count(b"\r\n", 0, size) != carriage_return_pending:
                return False
        first = buffer.find(b"\n", 0, size)
        if first < 0:
            run += size
            if run > MAX_LINE_BYTES:
                return False
            continue
        if run + first > MAX_LINE_BYTES:
            return False
        run = size - buffer.rfind(b"\n", 0, size) - 1


class _ScreenThread(threading.Thread):
    """_screen_rest of a file descriptor from an offset, in a thread; `passed` is its answer (False if it
    failed)."""

    def __init__(self, descriptor: int, offset: int):
        super().__init__(name="jointid log screen", daemon=True)
        self.descriptor, self.offset = descriptor, offset
        self.passed = False

    def run(self) -> None:
        try:
            self.passed = _screen_rest(self.descriptor, self.offset)
        except OSError:  # unreadable now: the chunked reading will say what is wrong
            self.passed = False


class _ColumnStore:
    """Parsed rows copied chunk by chunk into one column-major array sized from the file's length.

    Loading then holds about one copy of the numbers (plus a chunk) instead of a
    list of blocks and their concatenation, and every column is contiguous.
    """

    def __init__(self, width: int, total_bytes: int):
        self.width, self.total_bytes = width, total_bytes
        self.values = np.empty((width, 0))
        self.rows = 0

    def append(self, block: np.ndarray, text_bytes: int) -> None:
        """Store a (n, width) block parsed from `text_bytes` bytes of the file."""
        count = len(block)
        needed = self.rows + count
        capacity = self.values.shape[1]
        if needed > capacity:
            # Estimate the final row count from this chunk's bytes per row (2 % spare).
            guess = int(self.total_bytes * count / text_bytes * 1.02) + count
            grown = np.empty((self.width, max(needed, guess, int(capacity * 1.25))))
            grown[:, : self.rows] = self.values[:, : self.rows]
            self.values = grown
        self.values[:, self.rows : needed] = block.T
        self.rows = needed

    def columns(self) -> list[np.ndarray]:
        """(rows,) contiguous views, one per column."""
        return [self.values[j, : self.rows] for j in range(self.width)]


_read_csv = None


def _pandas_read_csv():
    """pandas.read_csv, imported on first use (0.61 of a synthetic `jointid fit`'s start, bench_startup_budget),
    or None if pandas is missing."""
    global _read_csv
    if _read_csv is None:
        try:
            from pandas import read_csv
        except ImportError:
            read_csv = False
        _read_csv = read_csv
    return _read_csv or None



def _long_line(path: str, line: int) -> LogError:
    """The error for a line longer than MAX_LINE_BYTES."""
    size = f"{MAX_LINE_BYTES // (1 << 20)} MiB"
    return LogError(path, f"line is longer than {size}: not a CSV log of one sample per line", line)


def _shorten(text: str, limit: int = 30) -> str:
    """The text, cut with an ellipsis when longer than `limit` characters."""
    return text if len(text) <= limit else text[: limit - 1] + "…"


SEPARATOR_NAMES = {"\t": "tabs", ";": "semicolons", "|": "vertical bars"}
"""Separators a log from another tool may use instead of commas, by the name a message gives them."""


def _separator_hint(names: list[str]) -> str:
    """'; the header is separated by tabs, not commas' when a one-cell header holds another separator."""
    if len(names) != 1:
        return ""
    found = [name for separator, name in SEPARATOR_NAMES.items() if separator in names[0]]
    return f"; the header is separated by {found[0]}, not commas (save the log as comma-separated)" if found else ""


def _check_header(path: str, line: int, names: list[str], column_map: ColumnMap | None = None) -> dict[str, int]:
    """Map each recognised column (by name, alias or `column_map`) to its 1-based position; raise LogError for
    duplicates, a map naming a missing column, or missing required ones."""
    lowered = [name.lower() for name in names]

    def label(index: int) -> str:
        return f"{index + 1} ({names[index]!r})"

    try:
        found = match_columns(names, column_map, label)
    except ColumnProblem as problem:
        # The same name twice keeps its message from before aliases were recognised.
        twice = next(((key, lowered.index(key) + 1, i + 1) for i, key in enumerate(lowered)
                      if key in COLUMNS and lowered.index(key) < i), None)
        if twice is not None and (column_map is None or twice[0] not in dict(column_map.pairs)):
            key, first, second = twice
            raise LogError(path, f"column {key!r} appears twice (columns {first} and {second})", line) from None
        raise LogError(path, str(problem), line) from None
    positions = {key: index + 1 for key, index in found.items()}
    missing = [n for n in ("q", "tau") if n not in positions]
    if missing:
        hint = suggested_map(names, positions) or _separator_hint(names)
        raise LogError(path, f"missing required column {missing[0]!r} in the header{hint}", line)
    if "t" not in positions and not ("qd" in positions and "qdd" in positions):
        lacking = " and ".join(n for n in ("qd", "qdd") if n not in positions)
        raise LogError(path, f"missing column 't': without {lacking}, times are needed to estimate them"
                       f"{suggested_map(names, positions)}", line)
    return positions



def load_log(
    path,
    *,
    degrees: bool = False,
    window: int | None = DEFAULT_WINDOW,
    order: int = DEFAULT_ORDER,
    progress: ProgressCallback | None = None,
    cancel: CancelCheck | None = None,
    chunk_bytes: int = CHUNK_BYTES,
) -> JointLog:
    """Read a CSV joint log, estimate any missing qd/qdd, and return it ready to fit; LogError on any problem.

    The angle is read in jointid's own convention, unwrapped when wrapped (jointid.logs.angles); other
    conventions and column maps: request.load_joint_log.
    """
    from .angles import read_angle

    check_filter(window, order)
    table = read_table(path, progress=progress, cancel=cancel, chunk_bytes=chunk_bytes)
    return joint_log_from_table(read_angle(table, degrees=degrees), degrees=degrees, window=window, order=order)


