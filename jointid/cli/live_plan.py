"""What `jointid watch` runs, built from its flags: the live source, the incremental fit, the session between them
and the received log saved when it stops. The command line and the explorer's watch view drive the same plan."""

from __future__ import annotations

import argparse
import threading
from typing import TYPE_CHECKING, Callable

from ..options import DEFAULT_ORDER
from .arguments import UserError

if TYPE_CHECKING:
    from ..live.received import LiveSource, Received
    from ..present.watch import Saved
    from ..studies.watch_refresh import WatchRefresh
    from ..studies.watch_session import WatchSession


class WatchPlan:
    """A watch ready to run: `watch(on_refresh)` until it stops, then `save()` once."""

    def __init__(self, source: LiveSource, session: WatchSession, recorder, save_path: str | None,
                 force: bool) -> None:
        self.source = source
        self.session = session
        self.recorder = recorder
        """Keeps every block received (livesrc's received-log writer)."""
        self.save_path = save_path
        self.force = force
        self._saved: Saved | None = None
        self._save_lock = threading.Lock()

    @property
    def description(self) -> str:
        """The source in one line, for titles."""
        return self.source.description

    @property
    def effort(self) -> str:
        """'torque' or 'voltage'."""
        return self.source.effort

    def watch(self, on_refresh: Callable[[WatchRefresh], None]) -> str:
        """Run the session until it stops (closing the source then); how it stopped."""
        try:
            return self.session.run(on_refresh)
        finally:
            self.source.close()

    def stop(self) -> None:
        """Ask the watch to stop (from any thread)."""
        self.session.stop()

    def save(self) -> Saved:
        """Write what was received to --save (once; later calls return the first answer): a present.watch.Saved."""
        from ..present.watch import Saved

        with self._save_lock:
            if self._saved is None:
                self._saved = self._write(Saved)
            return self._saved

    def _write(self, saved_type) -> Saved:
        count = self.recorder.count
        if self.save_path is None:
            return saved_type(None, count, "no --save PATH given")
        if count == 0:
            return saved_type(None, 0, "no sample was received")
        try:
            written = self.recorder.write(self.save_path, overwrite=self.force)
        except (OSError, ValueError) as error:  # the disk filled, the folder went: said, never a traceback
            return saved_type(None, count, f"{self.save_path} could not be written: {error}")
        return saved_type(self.save_path, written)


def open_watch(args: argparse.Namespace, refresh_hz: float) -> WatchPlan:
    """The source, fit and session the flags ask for; UserError (one line) for a source that cannot be opened."""
    from ..studies.watch_session import WatchSession

    source = open_source(args)
    try:
        refitter = new_refitter(args, source)
        recorder = new_recorder(args, source)
    except BaseException:
        source.close()
        raise
    session = WatchSession(source, refitter, refresh_hz=refresh_hz, duration=args.duration, record=recorder.add)
    return WatchPlan(source, session, recorder, args.save, args.force)


def live_reading(args: argparse.Namespace):
    """How arriving values become what is fitted (--degrees, --zero, --clockwise, the effort flags): a
    live.reading.LiveReading; UserError on a bad mix of the effort flags."""
    from dataclasses import replace

    from ..live.reading import LiveReading
    from ..logs.conventions import AngleConvention
    from .effort_arguments import effort_reading

    effort = effort_reading(args)
    if args.effort_scale is not None:
        effort = replace(effort, scale=args.effort_scale)
    return LiveReading(bool(args.degrees), AngleConvention(args.zero or "right", bool(args.clockwise)), effort)


def open_source(args: argparse.Namespace) -> LiveSource:
    """The growing CSV or the NetworkTables subscription of the flags; UserError when it cannot be opened."""
    from ..logs.table import LogError

    reading = live_reading(args)
    try:
        if args.csv is not None:
            from ..live.growing_csv import GrowingCsv

            return GrowingCsv(args.csv, columns=args.columns, reading=reading, duration=args.duration)
        return open_network_tables(args, reading)
    except LogError as error:
        raise UserError(str(error)) from None


def open_network_tables(args: argparse.Namespace, reading) -> LiveSource:
    """The NetworkTables 4 subscription of --nt and --entry (jointid.live's)."""
    try:
        from ..live.network_tables import NetworkTablesSource
    except ImportError:
        raise UserError("--nt: this build has no NetworkTables source yet (jointid.live.network_tables)") from None
    host, port = args.nt
    return NetworkTablesSource(host, port, args.entry, reading=reading, units=args.units, duration=args.duration)


def new_refitter(args: argparse.Namespace, source: LiveSource):
    """The incremental fit of the flags' model, effort, motor, filtering and conventions (studies.watch.Watcher)."""
    try:
        from ..studies.watch import Watcher
    except ImportError:
        raise UserError("watching needs the incremental fit (jointid.studies.watch), which this build does not "
                        "have yet") from None
    from ..logs.derivatives import FilterSettingError

    # The angle's convention and the effort's conversion are the source's (live.reading): its q is jointid's.
    try:
        return Watcher(model=args.model, mechanism=args.mechanism, effort=source.effort, linear=source.linear,
                       window=args.window, order=DEFAULT_ORDER if args.order is None else args.order,
                       cutoff=args.cutoff, decimate=args.decimate, robust=not args.no_robust)
    except FilterSettingError as error:
        raise UserError(f"argument --{error.field}: {error.problem}") from None


class ReceivedRecorder:
    """Every sample received, kept to be written as a CSV log that `jointid fit --csv` reads (t, q, qd, qdd, tau as
    they were fitted: SI units, jointid's angle convention)."""

    COLUMNS = ("t", "q", "qd", "qdd", "tau")

    def __init__(self) -> None:
        self.blocks: list[dict] = []
        self.count = 0

    def add(self, block: Received) -> None:
        """Keep a block's numeric columns."""
        if block.count:
            self.blocks.append({name: block.columns[name] for name in self.COLUMNS if name in block.columns})
            self.count += block.count

    def write(self, path: str, overwrite: bool = False) -> int:
        """Write the samples atomically (jointid.files); the number written. ExportError when it cannot."""
        import numpy as np

        from ..files import atomic_output

        names = [name for name in self.COLUMNS if all(name in block for block in self.blocks)]
        table = np.column_stack([np.concatenate([block[name] for block in self.blocks]) for name in names])
        with atomic_output(path, overwrite=overwrite) as handle:
            # 17 significant digits: reading the file back gives the same doubles.
            np.savetxt(handle, table, delimiter=",", fmt="%.17g", header=",".join(names), comments="")
        return len(table)


def new_recorder(args: argparse.Namespace, source: LiveSource):
    """The received-log writer, fed every block."""
    return ReceivedRecorder()
