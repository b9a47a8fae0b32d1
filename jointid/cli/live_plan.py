"""What `jointid watch` runs, built from its flags: the live source, the incremental fit, the session between them
and the received log saved when it stops. The command line and the explorer's watch view drive the same plan."""

from __future__ import annotations

import argparse
import threading
from typing import TYPE_CHECKING, Callable

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


def open_source(args: argparse.Namespace) -> LiveSource:
    """The growing CSV or the NetworkTables subscription of the flags; UserError when it cannot be opened."""
    raise UserError("watching needs jointid.live's sources, which this build does not have yet")


def new_refitter(args: argparse.Namespace, source: LiveSource):
    """The incremental fit of the flags' model, effort, motor, filtering and conventions (studies.watch.Watcher)."""
    raise UserError("watching needs jointid.studies.watch, which this build does not have yet")


def new_recorder(args: argparse.Namespace, source: LiveSource):
    """The received-log writer, fed every block (jointid.live's)."""
    raise UserError("watching needs jointid.live's received log, which this build does not have yet")

