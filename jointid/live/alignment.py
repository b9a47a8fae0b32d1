"""Topics published at their own times, put on one time base as they arrive, as a data log's entries are
(jointid.logs.wpilog): the position's time stamps (the velocity's without one), every other number interpolated
linearly at them (a robot loop publishes its values microseconds apart, so this is their own value), the SysId
test under way the last one recorded up to STATE_LAG (and less than half a step) after the sample.

A sample waits until every other topic has a record at or after it, so that nothing is extrapolated. It is left
out where another topic's neighbouring records are more than GAP_STEPS of its median steps apart (a gap), or
when that topic has sent nothing for HOLD_SECONDS of the base topic's time after it (it stopped publishing).
"""

from __future__ import annotations

from collections import deque

import numpy as np

from ..logs.wpilog import GAP_STEPS, NEAR_STEPS, STATE_LAG

HOLD_SECONDS = 1.0
"""Seconds of the base topic's time a sample waits for another topic's record before it is left out."""

RECENT_STEPS = 256
"""Steps of each topic kept to estimate its median step."""

NO_STATE = "none"
"""The state of a sample before any test-state record (SysId's own word between tests)."""


class _Topic:
    """The records of one topic not yet used, and its recent steps."""

    def __init__(self):
        self.times: list[float] = []
        self.values: list = []
        self.steps: deque = deque(maxlen=RECENT_STEPS)
        self.last: float | None = None

    def add(self, time: float, value) -> None:
        """One record (in arrival order; one older than the last is put in its place)."""
        if self.last is not None:
            self.steps.append(time - self.last)
        if self.times and time < self.times[-1]:
            at = int(np.searchsorted(self.times, time, side="right"))
            self.times.insert(at, time)
            self.values.insert(at, value)
        else:
            self.times.append(time)
            self.values.append(value)
        self.last = time if self.last is None else max(self.last, time)

    def median_step(self) -> float:
        """The median of its recent positive steps (0 without one)."""
        positive = [step for step in self.steps if step > 0]
        return float(np.median(positive)) if positive else 0.0

    def keep_from(self, index: int) -> None:
        """Forget the records before `index`."""
        if index > 0:
            del self.times[:index]
            del self.values[:index]


class TopicAligner:
    """Rows on the base topic's time stamps from the records of several topics (see the module's notes)."""

    def __init__(self, quantities, base: str, state: bool = False):
        """`quantities`: the numeric ones ('q', 'qd', 'qdd', 'tau'), `base` among them; `state`: a test-state
        topic too."""
        self.base = base
        self.others = tuple(name for name in quantities if name != base)
        self.topics = {name: _Topic() for name in (base, *self.others)}
        self.state = _Topic() if state else None

    def add(self, quantity: str, time: float, value) -> None:
        """One record of a quantity's topic ('state' for the test-state topic), at `time` seconds."""
        (self.state if quantity == "state" else self.topics[quantity]).add(time, value)

    def take(self, final: bool = False) -> tuple[dict[str, np.ndarray], int]:
        """(the rows ready, as columns 't', the quantities and maybe 'state'; the base samples left out).
        `final`: the stretch is over, so no later record will come: every sample is settled now."""
        base = self.topics[self.base]
        if not base.times:
            return {}, 0
        times = np.asarray(base.times)
        newest = times[-1]
        waiting_over = final | (times < newest - HOLD_SECONDS)
        ready = np.ones(len(times), dtype=bool)
        keep = np.ones(len(times), dtype=bool)
        columns = {"t": times, self.base: np.asarray(base.values, dtype=float)}
        for name in self.others:
            values, arrived, inside = self._at(self.topics[name], times)
            ready &= arrived | waiting_over
            keep &= inside
            columns[name] = values
        if self.state is not None:
            stamps = np.asarray(self.state.times)
            ready &= (len(stamps) > 0 and stamps[-1] >= times) | waiting_over
        settled = int(np.argmin(ready)) if not ready.all() else len(times)  # in order: the first not ready stops
        rows = keep[:settled]
        out = {name: column[:settled][rows] for name, column in columns.items()}
        if self.state is not None:
            out["state"] = self._states(out["t"])
        self._forget(settled, out["t"][-1] if len(out["t"]) else None)
        return out, int(settled - np.count_nonzero(rows))

    @staticmethod
    def _at(topic: _Topic, times: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(the topic's values interpolated at `times`, True where it has a record at or after the time, True where
        the sample is kept: its records either side are near enough)."""
        if not topic.times:
            nothing = np.zeros(len(times), dtype=bool)
            return np.zeros(len(times)), nothing, nothing
        stamps = np.asarray(topic.times)
        values = np.interp(times, stamps, np.asarray(topic.values, dtype=float))
        arrived = times <= stamps[-1]
        median = topic.median_step()
        after = np.clip(np.searchsorted(stamps, times, side="left"), 0, len(stamps) - 1)
        before = np.clip(after - 1, 0, len(stamps) - 1)
        nearest = np.minimum(np.abs(stamps[after] - times), np.abs(times - stamps[before]))
        within = (times >= stamps[0]) & arrived
        bracketed = within & (stamps[after] - stamps[before] <= GAP_STEPS * median)
        # As a data log's: a record within NEAR_STEPS of a step is the same loop's, even just before the first.
        return values, arrived, bracketed | (arrived & (nearest <= NEAR_STEPS * median))

    def _state_lag(self) -> float:
        """Seconds a state record may follow a sample and be its own: STATE_LAG, but less than half a step of the
        base topic (at 1 kHz the next loop's state is 1 ms later)."""
        step = self.topics[self.base].median_step()
        return min(STATE_LAG, 0.5 * step) if step > 0 else STATE_LAG

    def _states(self, times: np.ndarray) -> np.ndarray:
        """The test under way at each time: the last state recorded up to _state_lag after it."""
        stamps = np.asarray(self.state.times)
        index = np.searchsorted(stamps, times + self._state_lag(), side="right") - 1
        texts = np.asarray([*self.state.values, NO_STATE], dtype=object)
        return texts[np.where(index >= 0, index, len(stamps))].astype(str)

    def _forget(self, settled: int, last: float | None) -> None:
        """Drop the base samples settled, and every other record no later sample can need."""
        self.topics[self.base].keep_from(settled)
        if last is None:
            return
        for topic in (*(self.topics[name] for name in self.others), self.state):
            if topic is not None and topic.times:
                # Keep the last record at or before `last` (a later sample's bracket, or its state).
                index = int(np.searchsorted(topic.times, last + (self._state_lag() if topic is self.state else 0.0),
                                            side="right")) - 1
                topic.keep_from(index)

    def clear(self) -> None:
        """Forget everything (a new stretch starts: nothing is interpolated across the break)."""
        for topic in (*self.topics.values(), self.state):
            if topic is not None:
                topic.times.clear()
                topic.values.clear()
                topic.steps.clear()
                topic.last = None
