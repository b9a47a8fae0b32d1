"""A log as read, before any check: its recognised columns, where each row is in the file, and the errors
every reader raises."""

from __future__ import annotations

import dataclasses
import os
from bisect import bisect_right
from dataclasses import dataclass
from typing import BinaryIO, Callable

from ..files import FileRefused, open_for_reading, shown_path
from ..text_safety import shown_name

COLUMNS = ("t", "q", "qd", "qdd", "tau")
"""Recognised column names, in the order the loader stores them."""

CHUNK_BYTES = 1 << 21
"""Bytes read and parsed at a time (2 MiB): progress every ~2 % of 100 MB. With pandas' reader, 1-16 MiB
measured alike here (load + fit of 1,000,000 rows within 0.29-0.31 s), so pandas' per-call cost does not matter."""

MIN_FIT_ROWS = 3
"""A fit of three parameters needs at least three samples."""

ProgressCallback = Callable[[int, int], None]
"""progress(bytes_read, total_bytes), called after each chunk."""

CancelCheck = Callable[[], bool]
"""cancel() -> True to stop loading (raises LoadCancelled)."""


class LogError(ValueError):
    """A problem with a log file; str() is one line naming the file, row and column."""

    def __init__(self, path, problem: str, row: int | None = None, column: str | None = None, *,
                 place: str | None = None):
        self.path = os.fspath(path)
        self.problem = problem
        self.row = row
        self.column = column
        where = [shown_path(self.path)]  # a newline escaped: the message stays one line
        if row is not None:
            where.append(f"row {row}")
        if place is not None:  # where a row number does not apply, e.g. "message 12 on /joint_states"
            where.append(place)
        if column is not None:
            where.append(f"column {column}")
        super().__init__(f"{', '.join(where)}: {problem}")


class LoadCancelled(Exception):
    """Loading stopped because the cancel check returned True."""


@dataclass(frozen=True, eq=False)
class LogTable:
    """The recognised numeric columns of a CSV log, as read (no unit conversion)."""

    path: str
    """The file's path as given."""
    columns: dict
    """Name -> (N,) float array, for each recognised column present."""
    positions: dict
    """Name -> 1-based column position in the file."""
    ignored: tuple[str, ...]
    """Header names of the columns that were not used, in file order."""
    segments: tuple[tuple[int, int], ...]
    """(index of the first data row, byte offset in the file) of each parsed chunk."""
    notes: tuple[str, ...] = ()
    """Sentences about how the table was read or cut, for the fit's notes."""
    first: int = 0
    """Data rows cut from the start (a time window), so messages still name the file's lines."""
    time_window: object = None
    """The timewindow.TimeWindow the table was cut to, or None."""
    effort_scale: float = 1.0
    """Torque (N m) per unit of the logged tau or effort, already applied to the tau column (volts per unit for a
    voltage log)."""
    effort: str = "torque"
    """What the logged effort column measured: 'torque', 'current' (now converted to torque) or 'voltage'."""
    current_to_torque: tuple[float, float, float] | None = None
    """(gear, kt in N m/A, efficiency) a current log was converted to torque with, or None."""
    time_origin: float | None = None
    """The first time stamp of the log as read, when a time window has cut it (None: the first t here)."""

    @property
    def start_time(self) -> float | None:
        """The log's first time stamp as read (s), from which windows and exclusions count; None without t."""
        if self.time_origin is not None:
            return self.time_origin
        t = self.columns.get("t")
        return None if t is None or not len(t) else float(t[0])
    read_as: tuple[tuple[str, str], ...] = ()
    """(quantity, the column's name in the log) for each column read, e.g. ('q', 'position')."""
    angle: object = None
    """The conventions.AngleReading of the q column (zero, direction, wraps, turns), or None: jointid's own."""

    @property
    def origin(self) -> dict:
        """JSON-ready: the file, its format, and the time window and effort scale applied."""
        return {"path": shown_name(self.path), "format": "csv",
                "time_window": None if self.time_window is None else self.time_window.to_dict(),
                "effort_scale": self.effort_scale, **self.effort_origin}

    @property
    def effort_origin(self) -> dict:
        """JSON-ready: what the effort was, when not torque (a torque log's origin keeps its keys as before)."""
        if self.effort == "torque":
            return {}
        if self.current_to_torque is None:
            return {"effort": self.effort}
        gear, kt, efficiency = self.current_to_torque
        return {"effort": self.effort, "gear": gear, "kt_n_m_per_a": kt, "efficiency": efficiency}

    @property
    def count(self) -> int:
        """N, the number of data rows."""
        return len(next(iter(self.columns.values())))

    @property
    def description(self) -> str:
        """'1000 rows': what was read, for the line above the readouts."""
        return f"{self.count} rows"

    @property
    def brief(self) -> str:
        """What was read in a few words, for a narrow panel: '1000 rows'."""
        return self.description

    def sliced(self, rows: slice, note: str) -> "LogTable":
        """The table cut to a contiguous range of data rows, with a note saying how."""
        columns = {name: values[rows] for name, values in self.columns.items()}
        return dataclasses.replace(self, columns=columns, first=self.first + rows.start, notes=(*self.notes, note))

    def line_of(self, index: int) -> int:
        """1-based line number in the file of data row `index` (0-based); rereads the file, for messages only."""
        index += self.first
        k = bisect_right([s[0] for s in self.segments], index) - 1
        first, offset = self.segments[k]
        return _line_of_data_row(self.path, offset, index - first)

    def column_label(self, name: str) -> str:
        """'3 (qd)' or '3 (velocity)': the position and header name of a column, for messages."""
        return f"{self.positions[name]} ({self.header_of(name)})"

    def header_of(self, name: str) -> str:
        """The column's name in the log when it is not the quantity's own (e.g. 'velocity'), else the quantity."""
        header = dict(self.read_as).get(name, name)
        return name if header.strip().lower() == name else header

    def error(self, problem: str, index: int | None = None, name: str | None = None) -> LogError:
        """A LogError at data row `index` and column `name` (either may be None)."""
        row = None if index is None else self.line_of(index)
        return LogError(self.path, problem, row, None if name is None else self.column_label(name))



def _reopen(path: str) -> BinaryIO:
    """A log read before, opened again to find a line number for a message; LogError if it is no longer readable."""
    try:
        return open_for_reading(path)
    except FileRefused as error:
        raise LogError(path, error.problem) from None


def count_newlines(path: str, end: int) -> int:
    """Newlines in the file's first `end` bytes."""
    count = 0
    with _reopen(path) as handle:
        while end > 0:
            data = handle.read(min(end, CHUNK_BYTES))
            if not data:
                break
            count += data.count(b"\n")
            end -= len(data)
    return count


def _line_of_data_row(path: str, offset: int, index: int) -> int:
    """1-based line number of the `index`-th data line (0-based) at or after byte `offset`."""
    line = count_newlines(path, offset)
    with _reopen(path) as handle:
        handle.seek(offset)
        for text in handle:
            line += 1
            stripped = text.strip()
            if stripped and not stripped.startswith(b"#"):
                if index == 0:
                    return line
                index -= 1
    raise IndexError("data row beyond the end of the file")


