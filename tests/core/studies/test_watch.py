"""The live identification (studies.watch): simulated joints fed in blocks converge to their truth, declare a
parameter determined no earlier than an offline fit of the same samples allows, agree with that fit at the end,
and hold bounded state however long they run."""

from __future__ import annotations

import numpy as np
import pytest

from jointid.live.received import Received
from jointid.studies.watch import Watcher
from tests.support.watched_joints import arm, flywheel


def watched(samples, size: int, **settings) -> tuple[Watcher, list]:
    """A Watcher fed the samples in blocks of `size`, and its refresh after each second of them."""
    watcher = Watcher(**settings)
    refreshes = []
    per_second = max(1, int(round(1 / (samples.t[1] - samples.t[0]) / size)))
    for k, block in enumerate(samples.blocks(size)):
        watcher.add(Received(block))
        if (k + 1) % per_second == 0:
            refreshes.append(watcher.refresh())
    refreshes.append(watcher.refresh())
    return watcher, refreshes


@pytest.mark.parametrize("rate, size", [(50.0, 1), (1000.0, 50)])
def test_an_arm_converges_to_its_truth(rate, size):
    samples = arm(rate, 60.0)
    _, refreshes = watched(samples, size)
    final = refreshes[-1]
    for trace in final.parameters:
        truth = samples.truth[trace.name]
        assert abs(trace.value - truth) <= 0.05 * abs(truth), trace
        assert trace.verdict == "well determined", trace
        assert trace.determined_at is not None and trace.determined_at < final.elapsed
        assert len(trace.history) >= 2


@pytest.mark.parametrize("rate, size", [(50.0, 1), (1000.0, 50)])
def test_a_flywheel_converges_to_its_gains(rate, size):
    samples = flywheel(rate, 60.0)
    _, refreshes = watched(samples, size, effort="voltage", mechanism="simple")
    final = refreshes[-1]
    assert [trace.name for trace in final.parameters] == ["kA", "kV", "kS"]
    for trace in final.parameters:
        truth = samples.truth[trace.name]
        assert abs(trace.value - truth) <= 0.05 * abs(truth), trace


def test_state_stays_bounded_over_ten_times_the_samples():
    # Ten minutes at 50 Hz, a refresh a second: the state's size cycles (batches merge, histories thin, rows wait
    # for the robust step) but does not grow; a state that kept its rows would double from one half to the next.
    samples = arm(50.0, 600.0)
    watcher = Watcher()
    sizes = []
    for block in samples.blocks(50):
        watcher.add(Received(block))
        watcher.refresh()
        sizes.append(watcher.state_size)
    minute = len(sizes) // 10
    middle = (minute + len(sizes)) // 2
    first, second = max(sizes[minute:middle]), max(sizes[middle:])
    assert second <= 1.25 * first, (first, second)
