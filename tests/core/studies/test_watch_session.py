"""The watch session: blocks polled from a source reach the fit merged once per refresh, every block reaches the
recorder, and the watch ends on stop(), --duration, the source's end or a bad line, its last refresh `ended`."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from jointid.live.received import Received
from jointid.logs.table import LogError
from jointid.studies.watch_refresh import WatchRefresh
from jointid.studies.watch_session import (
    DURATION,
    SOURCE_ENDED,
    SOURCE_FAILED,
    STOPPED,
    WatchSession,
    merged,
)


class FakeClock:
    """Time that moves only when the source is polled: each poll takes the time it was allowed."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


class ScriptedSource:
    """Hands out its blocks one per poll, each poll taking `step` seconds of the fake clock; then nothing."""

    description, effort, linear = "scripted", "torque", False

    def __init__(self, blocks, clock: FakeClock, step: float = 0.1, fail_after: int | None = None) -> None:
        self.blocks, self.clock, self.step, self.fail_after = list(blocks), clock, step, fail_after
        self.polls = 0

    def poll(self, timeout: float) -> Received:
        self.polls += 1
        if self.fail_after is not None and self.polls > self.fail_after:
            raise LogError("arm.csv", "line 9, column 'tau': 'x' is not a number")
        self.clock.now += min(self.step, timeout) if timeout > 0 else self.step
        return self.blocks.pop(0) if self.blocks else Received()

    def close(self) -> None:
        pass


class CountingRefitter:
    """Records what it was fed; returns a refresh holding the running count."""

    def __init__(self) -> None:
        self.fed: list[Received] = []
        self.total = 0

    def add(self, received: Received) -> None:
        self.fed.append(received)
        self.total += received.count
        self.ended = received.ended

    def refresh(self) -> WatchRefresh:
        return WatchRefresh(elapsed=0.0, received=self.total, fitted=self.total, dropped=0, parameters=(),
                            ended=self.ended)


def block(start: int, count: int, **kwargs) -> Received:
    t = np.arange(start, start + count) * 0.01
    return Received(columns={"t": t, "tau": np.sin(t)}, **kwargs)


def test_blocks_are_merged_once_per_refresh_and_every_sample_reaches_the_fit_and_the_recorder():
    clock = FakeClock()
    blocks = [block(10 * k, 10) for k in range(12)]
    source, refitter, recorded = ScriptedSource(blocks, clock, step=0.1), CountingRefitter(), []
    session = WatchSession(source, refitter, refresh_hz=2.0, duration=None, record=recorded.append, clock=clock)
    refreshes = []

    def on_refresh(refresh):
        refreshes.append(refresh)
        if refresh.received == 120:
            session.stop()

    assert session.run(on_refresh) == STOPPED
    assert sum(b.count for b in recorded) == 120 == refitter.total
    # 0.1 s a poll at 2 refreshes a second: one fit per half second of the clock (and the last), not one per block.
    assert len(refitter.fed) <= clock.now * 2 + 1 < len(blocks)
    t = np.concatenate([fed.columns["t"] for fed in refitter.fed if fed.count])
    assert np.array_equal(t, np.arange(120) * 0.01)
    assert refreshes[-1].ended and not any(r.ended for r in refreshes[:-1])
    assert session.last is refreshes[-1]


def test_the_source_ending_ends_the_watch_with_its_last_samples_fitted():
    clock = FakeClock()
    source = ScriptedSource([block(0, 5), block(5, 5, ended=True)], clock)
    refitter = CountingRefitter()
    session = WatchSession(source, refitter, refresh_hz=1.0, clock=clock)
    assert session.run(lambda refresh: None) == SOURCE_ENDED
    assert refitter.total == 10 and session.last.ended


def test_duration_ends_the_watch_on_the_clock():
    clock = FakeClock()
    source = ScriptedSource([], clock, step=0.05)
    session = WatchSession(source, CountingRefitter(), refresh_hz=4.0, duration=1.5, clock=clock)
    assert session.run(lambda refresh: None) == DURATION
    assert 1.5 <= clock.now < 1.5 + 0.05 + 1e-9


def test_a_bad_line_ends_the_watch_with_what_arrived_before_it_and_says_why():
    clock = FakeClock()
    source = ScriptedSource([block(0, 7), block(7, 3)], clock, fail_after=2)
    refitter, recorded = CountingRefitter(), []
    session = WatchSession(source, refitter, refresh_hz=4.0, record=recorded.append, clock=clock)
    assert session.run(lambda refresh: None) == SOURCE_FAILED
    assert refitter.total == 10 and "line 9" in session.failure
    assert any("stopped reading" in event for fed in refitter.fed for event in fed.events)


def test_stop_from_another_thread_is_seen_within_a_poll():
    class Waiting(ScriptedSource):
        def poll(self, timeout):
            started.set()
            return Received()

    started = threading.Event()
    session = WatchSession(Waiting([], FakeClock()), CountingRefitter(), refresh_hz=4.0)
    stopper = threading.Thread(target=lambda: (started.wait(), session.stop()))
    stopper.start()
    assert session.run(lambda refresh: None) == STOPPED
    stopper.join()


def test_merged_offsets_each_blocks_breaks_and_adds_up_drops_and_events():
    one = block(0, 4, breaks=(0,), events=("connected",), dropped=2)
    two = block(4, 3, breaks=(1,), events=("reconnected after a 2.0 s gap (not bridged)",), dropped=1)
    joined = merged([one, Received(), two])
    assert joined.count == 7 and joined.breaks == (0, 5) and joined.dropped == 3
    assert joined.events == ("connected", "reconnected after a 2.0 s gap (not bridged)")
    assert not joined.ended and merged([one, Received(ended=True)]).ended


def test_refresh_rate_must_be_positive():
    with pytest.raises(ValueError, match="refresh_hz"):
        WatchSession(ScriptedSource([], FakeClock()), CountingRefitter(), refresh_hz=0)
