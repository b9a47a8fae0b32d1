"""Everything a live source handed over, written as a CSV log that every offline command reads and fits to the
same numbers (`jointid fit --csv`).

The columns are the quantities received, already in joint units (q in radians, or metres for a length; tau in N m,
or volts for a voltage source, which is read back with --effort voltage), each value at the digits that read back
to the same double; a SysId `state` column when the source had one (the CSV reader ignores it; GrowingCsv reads
it). Comment lines say where the samples came from, their units and how to fit them, and each event where it
happened. A new stretch (a reconnection, a file replaced) keeps its gap in time, never filled: the CSV reader then
fits the rows as they are when qd and qdd were received, and otherwise refuses to estimate derivatives across
the gap, naming it, as it would for a recorded log; `--train-window` fits one stretch.

The rows go to a temporary file beside the destination as they arrive (memory stays bounded however long the
watch) and the file takes its name only when the log is finished (jointid.files: atomically, and never over an
existing file without `overwrite`). A log abandoned leaves nothing behind.
"""

from __future__ import annotations

import os
import re

import numpy as np

from ..files import atomic_output, shown_command
from .received import Received

COLUMN_ORDER = ("t", "q", "qd", "qdd", "tau", "state")
"""The columns of the written log, in this order, each when received."""

_UNSAFE_TEXT = re.compile(r"[,\r\n\x00-\x1f\x7f]")
"""Characters a state text cannot hold in a cell of one line."""


def _unit_line(columns: tuple[str, ...], effort: str, linear: bool) -> str:
    """'# units: t s, q rad, ...' for the columns written."""
    position = "m" if linear else "rad"
    units = {"t": "s", "q": position, "qd": f"{position}/s", "qdd": f"{position}/s^2",
             "tau": "V (motor voltage)" if effort == "voltage" else "N m", "state": "SysId test"}
    return "# units: " + ", ".join(f"{name} {units[name]}" for name in columns)


class ReceivedLog:
    """A CSV log written as blocks arrive and put in place by `finish()` (see the module's notes)."""

    def __init__(self, path, *, description: str, effort: str = "torque", linear: bool = False,
                 overwrite: bool = False):
        """Start the log at `path` (ExportError, or AlreadyExists without `overwrite`, before anything is
        received); `description`, `effort` and `linear` as the live source's."""
        self.path = os.fspath(path)
        self.description, self.effort, self.linear = description, effort, linear
        self._output = atomic_output(self.path, overwrite=overwrite)
        self.handle = self._output.__enter__()
        self.columns: tuple[str, ...] | None = None
        self.rows = 0
        self.stretches = 0
        self.pending: list[str] = []  # events said before the header, written after it
        self.open = True

    @classmethod
    def for_source(cls, path, source, *, overwrite: bool = False) -> ReceivedLog:
        """The log of a LiveSource (its description, effort and linear)."""
        return cls(path, description=source.description, effort=source.effort, linear=source.linear,
                   overwrite=overwrite)

    def write(self, block: Received) -> None:
        """Append a block's rows, with its events as comments where they happened and a stretch's start marked."""
        if not self.open:
            raise ValueError("the received log is already finished")
        for event in block.events:
            self._comment(f"event: {event}")
        if not block.count:
            return
        if self.columns is None:
            self._header(block)
        missing = [name for name in self.columns if name not in block.columns]
        if missing:
            raise ValueError(f"a block without {', '.join(missing)}: a log's columns cannot change")
        starts = set(block.breaks)
        if self.rows == 0:
            starts.add(0)
        cells = [self._cells(name, block.columns[name]) for name in self.columns]
        lines = []
        for row, values in enumerate(zip(*cells)):
            if row in starts:
                self.stretches += 1
                if self.stretches > 1:
                    lines.append(f"# stretch {self.stretches} starts here: its gap in time is kept, not bridged")
            lines.append(",".join(values))
        self.handle.write("\n".join(lines) + "\n")
        self.rows += block.count

    def _header(self, block: Received) -> None:
        """The comments and the header row, from the first block's columns."""
        self.columns = tuple(name for name in COLUMN_ORDER if name in block.columns)
        flags = " --effort voltage" if self.effort == "voltage" else ""
        lines = [f"# jointid watch: received from {_one_line(self.description)}",
                 _unit_line(self.columns, self.effort, self.linear),
                 f"# fit it: {shown_command(['jointid', 'fit', '--csv', self.path])}{flags}"]
        if self.linear:
            lines.append("# q is a length (m): fit a mechanism without an angle (--mechanism simple or elevator)")
        self.handle.write("\n".join(lines) + "\n" + ",".join(self.columns) + "\n")
        for text in self.pending:
            self.handle.write(f"# {text}\n")
        self.pending = []

    def _comment(self, text: str) -> None:
        """A comment line (after the header once there is one)."""
        text = _one_line(text)
        if self.columns is None:
            self.pending.append(text)
        else:
            self.handle.write(f"# {text}\n")

    @staticmethod
    def _cells(name: str, values: np.ndarray) -> list[str]:
        """The cells of one column: numbers at the digits that read back to the same doubles, texts cleaned."""
        if name == "state":
            return [_UNSAFE_TEXT.sub(" ", str(text)).strip() or "none" for text in values]
        return [repr(value) for value in np.asarray(values, dtype=float).tolist()]

    def finish(self) -> str:
        """Put the log in place; its path. ExportError if it cannot be; with no row received, nothing is written
        and ValueError says so."""
        if not self.open:
            return self.path
        if self.rows == 0:
            self.abandon()
            raise ValueError(f"nothing was received: {self.path} is not written")
        self.open = False
        self._output.__exit__(None, None, None)
        return self.path

    def abandon(self) -> None:
        """Stop without writing anything (the temporary file is removed)."""
        if not self.open:
            return
        self.open = False
        try:
            raise _Abandoned()
        except _Abandoned as abandoned:
            self._output.__exit__(_Abandoned, abandoned, abandoned.__traceback__)


class _Abandoned(Exception):
    """Thrown into the atomic writer so that it removes its temporary file."""


def _one_line(text: str) -> str:
    """The text with line breaks and other control characters as spaces (a comment stays one line)."""
    return re.sub(r"[\r\n\x00-\x1f\x7f]", " ", str(text))
