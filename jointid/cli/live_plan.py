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


SAVE_WAIT = 10.0
"""Seconds save() waits for a watch stopped from another thread to record its last blocks (it takes one poll)."""


class WatchPlan:
    """A watch ready to run: `watch(on_refresh)` until it stops, then `save()` once."""

    def __init__(self, source: LiveSource, session: WatchSession, recorder, save_path: str | None,
                 force: bool, gains_asked: bool = False, drive=None) -> None:
        self.source = source
        self.gains_asked = gains_asked
        """Whether --gains wpilib asked for the feedforward gains when the watch stops."""
        self.drive = drive
        """The motor (model.motors.MotorDrive) turning a torque fit into gains, or None."""
        self.session = session
        self.recorder = recorder
        """Takes every block received: live.received_log.ReceivedLog with --save, else a ReceivedCount."""
        self.save_path = save_path
        self.force = force
        self._saved: Saved | None = None
        self._save_lock = threading.Lock()
        self._watching = threading.Event()
        self._watched = threading.Event()

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
        self._watching.set()
        try:
            return self.session.run(on_refresh)
        finally:
            self.source.close()
            self._watched.set()

    def final_gains(self):
        """The WPILib feedforward gains of the last refresh's fit (studies.gains.ArmGains), or None when they were
        not asked for or there is no unique fit."""
        last = self.session.last
        if not self.gains_asked or last is None:
            return None
        return self.session.refitter.gains(last, self.drive)

    def stop(self) -> None:
        """Ask the watch to stop (from any thread)."""
        self.session.stop()

    def save(self) -> Saved:
        """Write what was received to --save (once; later calls return the first answer): a present.watch.Saved."""
        from ..present.watch import Saved

        if self._watching.is_set():  # a stop asked from another thread: the last blocks are still being recorded
            self._watched.wait(SAVE_WAIT)
        with self._save_lock:
            if self._saved is None:
                self._saved = self._write(Saved)
            return self._saved

    def _write(self, saved_type) -> Saved:
        count = self.recorder.rows
        if self.save_path is None:
            return saved_type(None, count, "no --save PATH given")
        if count == 0:
            self.recorder.abandon()
            return saved_type(None, 0, "no sample was received")
        try:
            path = self.recorder.finish()
        except (OSError, ValueError) as error:  # the disk filled, the folder went: said, never a traceback
            return saved_type(None, count, f"{self.save_path} could not be written: {error}")
        return saved_type(path, count)


def open_watch(args: argparse.Namespace, refresh_hz: float) -> WatchPlan:
    """The source, fit and session the flags ask for; UserError (one line) for a source that cannot be opened."""
    from ..studies.watch_session import WatchSession

    source = open_source(args)
    try:
        refitter = new_refitter(args, source)
        recorder = new_recorder(args, source)  # --save's temporary file is made now: a folder that refuses it is
    except BaseException:                      # said before anything is watched
        source.close()
        raise
    session = WatchSession(source, refitter, refresh_hz=refresh_hz, duration=args.duration, record=recorder.write)
    drive = None
    if args.gains is not None:
        from .effort_arguments import motor_drive

        drive = motor_drive(args)
    return WatchPlan(source, session, recorder, args.save, args.force, gains_asked=args.gains is not None,
                     drive=drive)


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
    """The growing CSV or the NetworkTables subscription of the flags (live.opening); UserError (one line) when it
    cannot be opened: a file refused, a host that does not answer, a topic missing or of the wrong type, pyntcore
    not installed."""
    from ..live.opening import open_live_source

    try:
        return open_live_source(nt=args.nt, csv=args.csv, entries=args.entry, columns=args.columns,
                                reading=live_reading(args), units=args.units, duration=args.duration,
                                gone_timeout=args.gone)
    except ValueError as error:  # LogError, NetworkTablesError: one line each
        raise UserError(str(error)) from None


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


class ReceivedCount:
    """Without --save: what was received is only counted (the last line says nothing was written, and why)."""

    def __init__(self) -> None:
        self.rows = 0

    def write(self, block: Received) -> None:
        """Count a block's samples."""
        self.rows += block.count


def new_recorder(args: argparse.Namespace, source: LiveSource):
    """Where every block received goes: the received log of --save (live.received_log, written to a temporary
    file beside PATH as blocks arrive, put in place when the watch stops), or a count without it."""
    if args.save is None:
        return ReceivedCount()
    from ..files import ExportError
    from ..live.received_log import ReceivedLog

    try:
        return ReceivedLog.for_source(args.save, source, overwrite=args.force)
    except ExportError as error:
        raise UserError(f"--save {error}") from None
