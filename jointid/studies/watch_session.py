"""One watch from start to stop: poll a live source, hand what arrived to the incremental fit at a steady rate,
and stop on request, at --duration, or when the source ends. The command line runs it on its main thread, the
explorer in a worker thread; both see the same refreshes."""

from __future__ import annotations

import threading
import time
from typing import Callable, Iterable, Protocol

import numpy as np

from ..live.received import LiveSource, Received
from ..logs.table import LogError
from .watch_refresh import WatchRefresh

DEFAULT_REFRESH_HZ = 4.0
"""Refreshes a second by default: several a second, as a team at the robot expects, with room for the fit."""

LONGEST_POLL = 0.25
"""The longest a poll waits, in seconds, so a stop request is seen within it whatever the refresh rate."""

STOPPED = "stopped"
"""How a watch ended: stop() was called (q in the explorer, Ctrl+C on the command line)."""
DURATION = "duration"
"""How a watch ended: --duration seconds passed."""
SOURCE_ENDED = "source ended"
"""How a watch ended: the source said it is finished for good (or is gone)."""
SOURCE_FAILED = "source failed"
"""How a watch ended: the source could not be read on (a bad line in a CSV); `failure` says why."""


class Refitter(Protocol):
    """The incremental identification (studies.watch.Watcher): given each merged block, asked for a refresh."""

    def add(self, received: Received) -> None:
        """Take the samples, events, drops and end of `received`."""

    def refresh(self) -> WatchRefresh:
        """What the faces show now."""


def merged(blocks: Iterable[Received]) -> Received:
    """Several blocks as one: columns joined in order, events in order, drops added up, stretch breaks kept,
    ended if any ended.

    A column missing from some blocks that carry samples is dropped, so every array keeps the same length.
    """
    blocks = list(blocks)
    with_samples = [block for block in blocks if block.count]
    columns: dict[str, np.ndarray] = {}
    if with_samples:
        shared = set(with_samples[0].columns).intersection(*(block.columns for block in with_samples[1:]))
        columns = {name: np.concatenate([np.asarray(block.columns[name]) for block in with_samples])
                   for name in with_samples[0].columns if name in shared}
    breaks, offset = [], 0
    for block in with_samples:  # each block's stretch starts, as rows of the joined block
        breaks.extend(offset + row for row in block.breaks)
        offset += block.count
    return Received(columns=columns, events=tuple(event for block in blocks for event in block.events),
                    dropped=sum(block.dropped for block in blocks), ended=any(block.ended for block in blocks),
                    breaks=tuple(breaks))


class WatchSession:
    """Polls `source`, keeps every block for `record` (the received log), and feeds the fit once per refresh."""

    def __init__(self, source: LiveSource, refitter: Refitter, *, refresh_hz: float = DEFAULT_REFRESH_HZ,
                 duration: float | None = None, record: Callable[[Received], None] | None = None,
                 clock: Callable[[], float] = time.monotonic) -> None:
        """A session that has not started; `record` sees every block as it arrives (before the fit does)."""
        if not refresh_hz > 0:
            raise ValueError(f"refresh_hz must be positive; got {refresh_hz!r}")
        self.source = source
        self.refitter = refitter
        self.period = 1.0 / refresh_hz
        self.duration = duration
        self.record = record
        self.clock = clock
        self.last: WatchRefresh | None = None
        """The latest refresh (the final one once run() has returned)."""
        self.failure: str | None = None
        """Why the source could not be read on (the watch then ends as SOURCE_FAILED), else None."""
        self._stop = threading.Event()

    def stop(self) -> None:
        """Ask the session to stop (from any thread); run() then gives the fit what arrived and returns."""
        self._stop.set()

    @property
    def stopping(self) -> bool:
        """Whether stop() was called."""
        return self._stop.is_set()

    def run(self, on_refresh: Callable[[WatchRefresh], None]) -> str:
        """Watch until stopped, --duration or the source's end, calling on_refresh with each refresh (the last
        has `ended` set); how it ended (STOPPED, DURATION, SOURCE_ENDED or SOURCE_FAILED)."""
        start = self.clock()
        next_refresh = start + self.period
        pending: list[Received] = []
        while True:
            now = self.clock()
            ending = STOPPED if self._stop.is_set() else (
                DURATION if self.duration is not None and now - start >= self.duration else None)
            if ending is None:
                wait = min(max(next_refresh - now, 0.0), LONGEST_POLL)
                if self.duration is not None:
                    wait = min(wait, max(start + self.duration - now, 0.0))
                try:
                    block = self.source.poll(wait)
                except LogError as error:  # what arrived before the bad line is still fitted and saved
                    self.failure = str(error)
                    block = Received(events=(f"stopped reading: {self.failure}",), ended=True)
                if block.count or block.events or block.dropped or block.ended:
                    pending.append(block)
                    if self.record is not None:
                        self.record(block)
                if block.ended:
                    ending = SOURCE_FAILED if self.failure is not None else SOURCE_ENDED
            if ending is not None:
                if ending == SOURCE_FAILED and self.last is None and not any(b.count for b in pending):
                    return ending  # nothing to show: the failure (a header that cannot be read) is all there is
                # The last refresh says the watch is over, whatever stopped it (the contract's `ended`).
                self._refresh([*pending, Received(ended=True)], on_refresh)
                return ending
            if self.clock() >= next_refresh:
                self._refresh(pending, on_refresh)
                pending = []
                next_refresh = max(next_refresh + self.period, self.clock())  # a slow fit skips ticks, not piles them

    def _refresh(self, blocks: list[Received], on_refresh: Callable[[WatchRefresh], None]) -> None:
        """Feed the blocks as one and hand the refresh on."""
        self.refitter.add(merged(blocks))
        self.last = self.refitter.refresh()
        on_refresh(self.last)
