"""A CSV log being appended (a bench logger, a serial capture), read as it grows.

The header is read once, as jointid's CSV reader reads it (the same column names, aliases and --columns map,
jointid.logs.conventions), plus a `state` column of SysId test names when there is one. Then each poll reads the
complete lines written since the last: a last line without its newline is still being written, so it is left for
the next poll and never parsed half-written. Every cell read is checked as the CSV reader checks it, and a bad one
raises a LogError naming the file, the line and the column.

What happens to the file is said as an event: truncated (read again from its start) or replaced by a new file of
the same name (the old one is read to its end first); either starts a new stretch. The source ends when the
writer seems done (no new line for `idle_timeout` seconds) or when the samples span `duration` seconds; a last
line left without its newline then is said and left out, since it may be cut short.
"""

from __future__ import annotations

import io
import os
import time

import numpy as np

from ..files import FileRefused, open_for_reading, shown_path
from ..logs.conventions import ColumnMap
from ..logs.csv_reader import MAX_LINE_BYTES, _NUMBER, _check_header, _shorten
from ..logs.table import CHUNK_BYTES, COLUMNS, LogError
from .reading import LiveReading
from .received import Received
from .stretches import StretchClock
from .unwrapping import LiveUnwrap

STATE_COLUMN = "state"
"""The header name of a column of SysId test names (quasistatic-forward, ..., none), read as text."""

CHECK_INTERVAL = 0.02
"""Seconds between looks at the file while waiting for it to grow (as `tail -f` does)."""


class GrowingCsv:
    """A live source reading a CSV file as it is appended (see the module's notes)."""

    linear = False

    def __init__(self, path, *, columns=None, reading: LiveReading | None = None, idle_timeout: float | None = None,
                 duration: float | None = None, chunk_bytes: int = CHUNK_BYTES):
        """Open `path` (LogError when it cannot be read); `columns` a ColumnMap, 'q=posn,...' or mapping as the CSV
        reader takes; `idle_timeout` seconds without a new line that end the source (None: never);
        `duration` seconds of samples after which it ends (None: never)."""
        self.path = os.fspath(path)
        self.column_map = ColumnMap.of(columns, "--columns")
        self.reading = reading or LiveReading()
        for name, value in (("idle_timeout", idle_timeout), ("duration", duration)):
            if value is not None and not value > 0:
                raise ValueError(f"{name} must be a positive number of seconds or None; got {value!r}")
        self.idle_timeout, self.duration = idle_timeout, duration
        self.chunk_bytes = max(int(chunk_bytes), 1)
        self.description = f"growing CSV {shown_path(self.path)}"
        self.effort = self.reading.effort_kind
        self.handle = self._open()
        self.clock = StretchClock()
        self.unwrapping = LiveUnwrap()
        self.quantities: tuple[str, ...] | None = None  # the first header's: a new file must give the same
        self._reset_file()
        self.last_growth = time.monotonic()
        self.first_t: float | None = None
        self.ended = False
        self.pending_events: list[str] = list(self.reading.notes())

    # ------------------------------------------------------------------------------------------ the file

    def _open(self):
        """The file opened for reading (only a regular file: jointid.files); LogError otherwise."""
        try:
            return open_for_reading(self.path)
        except FileRefused as error:
            raise LogError(self.path, error.problem) from None

    def _reset_file(self) -> None:
        """Read the open file from its start: header first."""
        self.offset = 0
        self.line = 0  # lines of the file consumed so far
        self.header: list[str] | None = None
        self.positions: dict[str, int] = {}
        self.state_index: int | None = None
        self.last_t: float | None = None
        stat = os.fstat(self.handle.fileno())
        self.identity = (stat.st_dev, stat.st_ino)

    def _truncated(self) -> bool:
        """Notice a file truncated, or truncated and written again past where reading was (the line read last no
        longer ends there): read it again from its start, as a new stretch. True when it was."""
        size = os.fstat(self.handle.fileno()).st_size
        if size < self.offset:
            return self._restart(f"was truncated to {size} bytes")
        if self.offset and os.pread(self.handle.fileno(), 1, self.offset - 1) != b"\n":
            return self._restart("was written again from its start")
        return False

    def _restart(self, what: str) -> bool:
        """Read the (open) file from its start, as a new stretch, saying `what` happened to it; True."""
        self.pending_events.append(f"{shown_path(self.path)} {what}: reading it from its start (a new stretch)")
        self._reset_file()
        self.clock.new_stretch()
        return True

    def _check_file(self) -> bool:
        """Notice a file truncated (read again) or replaced (the new one read from its start); called when the
        open file has no complete line left, so the old one is read out first. True when reading starts again."""
        try:
            stat = os.stat(self.path)
        except OSError:
            return False  # removed (or not reachable now): what the open file holds is still read
        if (stat.st_dev, stat.st_ino) == self.identity:
            return False
        if self._peek_rest().strip():
            self.pending_events.append(f"{shown_path(self.path)}: the replaced file's line {self.line + 1} has no "
                                       "line end: left out (it may be cut short)")
        self.handle.close()
        self.handle = self._open()
        return self._restart("was replaced by a new file")

    def _peek_rest(self) -> bytes:
        """The bytes after the last complete line already read (a partial line), without consuming them."""
        self.handle.seek(self.offset)
        return self.handle.read(MAX_LINE_BYTES + 1)

    def _complete_lines(self) -> bytes:
        """The next run of complete lines (at most about chunk_bytes), consumed; b'' when none is complete."""
        self.handle.seek(self.offset)
        data = self.handle.read(self.chunk_bytes)
        cut = data.rfind(b"\n") + 1
        while not cut and len(data) >= self.chunk_bytes:  # one line longer than a chunk
            if len(data) > MAX_LINE_BYTES:
                raise LogError(self.path, "line is longer than 1 MiB: not a CSV log of one sample per line",
                               self.line + 1)
            more = self.handle.read(self.chunk_bytes)
            if not more:
                break
            data += more
            cut = data.rfind(b"\n") + 1
        self.offset += cut
        return data[:cut]

    # ------------------------------------------------------------------------------------------ parsing

    def _read_header(self, text: str) -> None:
        """Take the header's names and find the columns; LogError as the CSV reader's."""
        names = [cell.strip().strip('"').strip() for cell in text.split(",")]
        positions = _check_header(self.path, self.line, names, self.column_map)
        if "t" not in positions:
            raise LogError(self.path, "missing column 't': a log read as it grows needs its times", self.line)
        states = [i for i, name in enumerate(names) if name.lower() == STATE_COLUMN]
        self.state_index = states[0] if states else None
        quantities = (*sorted(positions), *(("state",) if states else ()))
        if self.quantities is not None and quantities != self.quantities:
            raise LogError(self.path, f"was truncated or replaced by a log of other columns ({', '.join(quantities)} "
                           f"instead of {', '.join(self.quantities)}); watch it anew", self.line)
        self.quantities = quantities
        self.header, self.positions = names, positions
        shown = ", ".join(f"{key}={names[positions[key] - 1]}" for key in COLUMNS if key in positions)
        state = f", state={names[self.state_index]}" if self.state_index is not None else ""
        self.pending_events.append(f"reading {shown_path(self.path)}: {shown}{state}")

    def _parse(self, data: bytes) -> tuple[dict, int]:
        """Rows of complete lines: {quantity: values} (and 'state': texts), and rows read; LogError at a bad one."""
        if self.header is not None and self.state_index is None and b"#" not in data:
            fast = self._parse_fast(data)
            if fast is not None:
                return fast
        return self._parse_lines(data)

    def _parse_fast(self, data: bytes) -> tuple[dict, int] | None:
        """The rows of plain numeric lines parsed by numpy's C reader (as the CSV reader's chunks are), or None
        when anything might be wrong: the line-by-line reading then names it."""
        buffer = np.frombuffer(data, dtype=np.uint8)
        ends = np.flatnonzero(buffer == ord("\n"))
        commas = np.diff(np.searchsorted(np.flatnonzero(buffer == ord(",")), ends), prepend=0)
        lengths = np.diff(ends, prepend=-1) - 1
        blank = (lengths == 0) | ((lengths == 1) & (buffer[np.maximum(ends - 1, 0)] == ord("\r")))
        if not np.all((commas == len(self.header) - 1) | blank):
            return None
        wanted = [key for key in COLUMNS if key in self.positions]
        try:
            values = np.loadtxt(io.BytesIO(data), delimiter=",", comments=None, ndmin=2, dtype=float,
                                usecols=[self.positions[key] - 1 for key in wanted])
        except ValueError:
            return None
        rows = int(np.count_nonzero(~blank))
        if values.shape != (rows, len(wanted)) or not np.isfinite(values).all():
            return None
        t = values[:, 0]
        if rows and ((self.last_t is not None and t[0] < self.last_t) or np.any(np.diff(t) < 0)):
            return None
        self.line += len(ends)
        if rows:
            self.last_t = float(t[-1])
        return {key: values[:, i] for i, key in enumerate(wanted)}, rows

    def _parse_lines(self, data: bytes) -> tuple[dict, int]:
        """_parse line by line, naming the line and column of a bad cell."""
        values: dict[str, list] = {key: [] for key in COLUMNS}
        states: list[str] = []
        rows = 0
        for raw in data.split(b"\n")[:-1]:
            self.line += 1
            if b"\x00" in raw:
                raise LogError(self.path, "holds NUL bytes: binary data or UTF-16/32 text; save it as UTF-8 or "
                               "ASCII text", self.line)
            text = raw.decode("utf-8", errors="replace").rstrip("\r")
            if self.line == 1:
                text = text.removeprefix("\ufeff")  # a UTF-8 byte order mark
            stripped = text.strip()
            if not stripped or stripped.startswith("#"):
                continue
            if self.header is None:
                self._read_header(stripped)
                continue
            wanted = [key for key in COLUMNS if key in self.positions]
            cells = text.split(",")
            if len(cells) != len(self.header):
                raise LogError(self.path, f"has {len(cells)} cells but the header has {len(self.header)} columns",
                               self.line)
            row = []
            for key in wanted:
                index = self.positions[key] - 1
                cell = cells[index].strip()
                label = f"{index + 1} ({self.header[index] or key})"
                if not _NUMBER.fullmatch(cell):
                    what = "is empty" if not cell else f"{_shorten(cell)!r} is not a number"
                    raise LogError(self.path, what, self.line, label)
                value = float(cell)
                if not np.isfinite(value):
                    raise LogError(self.path, f"{'NaN' if value != value else 'infinity'} is not a measurement",
                                   self.line, label)
                row.append(value)
            t = row[0]
            if self.last_t is not None and t < self.last_t:
                time_label = f"{self.positions['t']} ({self.header[self.positions['t'] - 1]})"
                raise LogError(self.path, f"time runs backwards: t = {t:.9g} s after {self.last_t:.9g} s on the "
                               "previous row", self.line, time_label)
            self.last_t = t
            for key, value in zip(wanted, row):
                values[key].append(value)
            if self.state_index is not None:
                states.append(cells[self.state_index].strip())
            rows += 1
        values = {key: found for key, found in values.items() if key in self.positions}
        if self.state_index is not None:
            values[STATE_COLUMN] = states
        return values, rows

    # ------------------------------------------------------------------------------------------ polling

    def poll(self, timeout: float) -> Received:
        """Wait up to `timeout` seconds for complete lines, then return the samples they hold (maybe none)."""
        if self.ended:
            return Received(ended=True)
        deadline = time.monotonic() + max(timeout, 0.0)
        while True:
            if self._truncated():
                continue
            data = self._complete_lines()
            if not data and self._check_file():
                continue
            if data:
                self.last_growth = time.monotonic()
                block = self._block(data)
                if block.count or block.events or block.ended:
                    return block
                continue  # only comments or the header: look again at once
            if self.idle_timeout is not None and time.monotonic() - self.last_growth >= self.idle_timeout:
                return self._end(f"no new line in {self.idle_timeout:g} s: the writer seems done")
            now = time.monotonic()
            if now >= deadline:
                return self._take_events(Received())
            time.sleep(min(CHECK_INTERVAL, deadline - now))

    def _block(self, data: bytes) -> Received:
        """The samples of complete lines as a Received block (cut at `duration`, which ends the source)."""
        starting = self.clock.starting
        values, rows = self._parse(data)
        if not rows:
            return self._take_events(Received())
        columns = {key: np.asarray(found, dtype=object if key == STATE_COLUMN else float)
                   for key, found in values.items()}
        if STATE_COLUMN in columns:
            columns[STATE_COLUMN] = columns[STATE_COLUMN].astype(str)
        columns = self.reading.convert(columns)
        if starting:
            self.unwrapping.restart()
        columns["q"], wrapped = self.unwrapping.unwrap(columns["t"], columns["q"])
        if wrapped:
            self.pending_events.append(wrapped)
        t, said = self.clock.place(columns["t"])
        columns["t"] = t
        if said:
            self.pending_events.append(said)
        if self.first_t is None:
            self.first_t = float(t[0])
        ended = False
        if self.duration is not None and float(t[-1]) - self.first_t >= self.duration:
            keep = int(np.searchsorted(t, self.first_t + self.duration, side="right"))
            columns = {key: column[:keep] for key, column in columns.items()}
            self.pending_events.append(f"{self.duration:g} s of samples read: done")
            self.ended = ended = True
        breaks = (0,) if starting and len(columns["t"]) else ()
        return self._take_events(Received(columns=columns, breaks=breaks, ended=ended))

    def _end(self, why: str) -> Received:
        """The block that ends the source: why, and any last line left without its newline; LogError when no
        header ever came (it is no log being written)."""
        rest = self._peek_rest()
        if self.header is None:
            self.ended = True
            what = "is empty" if not rest.strip() and self.line == 0 else "has no complete header row"
            raise LogError(self.path, f"{what}: no header row came ({why})")
        if rest.strip():
            self.pending_events.append(f"{shown_path(self.path)}: line {self.line + 1} has no line end: left out "
                                       "(it may be cut short)")
        self.pending_events.append(why)
        self.ended = True
        return self._take_events(Received(ended=True))

    def _take_events(self, block: Received) -> Received:
        """`block` with the events said since the last poll."""
        events, self.pending_events = tuple(self.pending_events), []
        if not events:
            return block
        return Received(columns=block.columns, events=events, dropped=block.dropped, ended=block.ended,
                        breaks=block.breaks)

    def close(self) -> None:
        """Stop reading and close the file."""
        self.ended = True
        self.handle.close()
