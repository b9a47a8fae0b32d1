"""A log held in memory (a dict of arrays or a pandas DataFrame) read as a table, checked like a file's."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np

from .conventions import ColumnMap, ColumnProblem, columns_note, match_columns, read_as, suggested_map
from .table import COLUMNS, LogError, LogTable

SOURCE_NAME = "arrays"
"""How messages and notes name a log given as arrays."""


@dataclasses.dataclass(frozen=True, eq=False)
class ArrayTable(LogTable):
    """Columns given as arrays; messages name the sample (0-based index, as the arrays count)."""

    @property
    def origin(self) -> dict:
        """LogTable.origin with format "arrays"."""
        return {**super().origin, "format": "arrays"}

    def line_of(self, index: int) -> int:
        """The sample's 0-based index in the arrays given."""
        return index + self.first

    def column_label(self, name: str) -> str:
        """The column's name."""
        return repr(dict(self.read_as).get(name, name))

    def error(self, problem: str, index: int | None = None, name: str | None = None) -> LogError:
        """A LogError naming the sample's index and the column."""
        where = [] if index is None else [f"sample {self.line_of(index)}"]
        if name is not None:
            where.append(f"column {self.column_label(name)}")
        return LogError(self.path, problem, place=", ".join(where) or None)

    @property
    def description(self) -> str:
        """What was read, for the line above the readouts."""
        return f"{self.count} samples"

    @property
    def brief(self) -> str:
        """What was read in a few words."""
        return self.description


def read_arrays(columns: Mapping, name: str = SOURCE_NAME, column_map: ColumnMap | None = None) -> ArrayTable:
    """The recognised columns (t, q, qd, qdd, tau by name, by the names loggers use, or as `column_map` names
    them) of a mapping of equal-length 1-D real arrays; LogError naming what is missing or wrong. A pandas
    DataFrame is such a mapping."""
    if not hasattr(columns, "keys") or not hasattr(columns, "__getitem__"):
        raise TypeError(f"a log's columns must be a mapping of arrays (a dict or a DataFrame); got "
                        f"{type(columns).__name__}")
    given = list(columns.keys())
    keys = [str(key) for key in given]
    try:
        found = match_columns(keys, column_map, flag="columns")
    except ColumnProblem as problem:
        raise LogError(name, str(problem)) from None
    missing = [key for key in ("q", "tau") if key not in found]
    if missing:
        hint = suggested_map(keys, found, column_map.flag if column_map is not None else "columns")
        raise LogError(name, f"no {' and no '.join(missing)} column; the columns are {', '.join(keys) or 'none'} "
                       f"(recognised: {', '.join(COLUMNS)}){hint}")
    read, length = {}, None
    for key in (key for key in COLUMNS if key in found):
        label = keys[found[key]]
        values = np.asarray(columns[given[found[key]]])
        if values.ndim != 1 or values.dtype.kind not in "biuf":
            shape = "a 1-D array of real numbers" if values.ndim == 1 else f"1-D, not of shape {values.shape}"
            raise LogError(name, f"must be {shape}; got {values.dtype} values", column=repr(label))
        if length is not None and len(values) != length:
            first = keys[found[next(iter(read))]]
            raise LogError(name, f"has {len(values)} values where {first!r} has {length}", column=repr(label))
        read[key], length = values.astype(float), len(values)
    positions = {key: found[key] + 1 for key in read}
    ignored = tuple(key for index, key in enumerate(keys) if index not in found.values())
    named = read_as(keys, found)
    note = columns_note(named)
    return ArrayTable(name, read, positions, ignored, ((0, 0),), notes=() if note is None else (note,),
                      read_as=named)
