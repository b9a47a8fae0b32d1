"""The one place a face opens a live source: a NetworkTables server (`--nt`) or a CSV being appended (`--csv`),
with the reading options a recorded log takes."""

from __future__ import annotations

from .reading import LiveReading


def open_live_source(*, nt: str | None = None, csv=None, entries=None, columns=None,
                     reading: LiveReading | None = None, units: str | None = None, duration: float | None = None,
                     idle_timeout: float | None = None, gone_timeout: float | None = None,
                     connect_timeout: float = 5.0):
    """A LiveSource: NetworkTablesSource for `nt` ('HOST[:PORT]', topics from `entries`) or GrowingCsv for `csv`
    (columns by name or `columns`); ValueError (one line: LogError, NetworkTablesError) when it cannot be opened."""
    if (nt is None) == (csv is None):
        raise ValueError("watch one source: --nt HOST[:PORT] or --csv FILE")
    if nt is not None:
        if columns is not None:
            raise ValueError("--columns: only for a CSV; name NetworkTables topics with --entry")
        from .network_tables import NetworkTablesSource

        return NetworkTablesSource(nt, entries, reading=reading, units=units, duration=duration,
                                   gone_timeout=gone_timeout, connect_timeout=connect_timeout)
    if entries is not None or units is not None:
        raise ValueError(f"{'--entry' if entries is not None else '--units'}: only for NetworkTables (--nt); a "
                         "CSV's columns are named with --columns and its angle read in radians or with --degrees")
    from .growing_csv import GrowingCsv

    return GrowingCsv(csv, columns=columns, reading=reading, idle_timeout=idle_timeout, duration=duration)
