"""The live identification (studies.watch): simulated joints fed in blocks converge to their truth, declare a
parameter determined no earlier than an offline fit of the same samples allows, agree with that fit at the end,
and hold bounded state however long they run."""

from __future__ import annotations

import numpy as np
import pytest

from jointid.live.received import Received
from jointid.studies.log_fit import fit_log
from jointid.studies.watch import Watcher
from tests.support.watched_joints import arm, flywheel


def watched(samples, size: int, **settings) -> tuple[Watcher, list]:
    """A Watcher fed the samples in blocks of `size`, and (samples received, refresh) after each second of them."""
    watcher = Watcher(**settings)
    refreshes = []
    per_second = max(1, int(round(1 / (samples.t[1] - samples.t[0]) / size)))
    for k, block in enumerate(samples.blocks(size)):
        watcher.add(Received(block))
        if (k + 1) % per_second == 0:
            refreshes.append((min((k + 1) * size, len(samples.t)), watcher.refresh()))
    refreshes.append((len(samples.t), watcher.refresh()))
    return watcher, refreshes


def offline(samples, count: int, watcher: Watcher, **settings):
    """jointid's log fit of the first `count` samples, with the low-pass, decimation and window the watcher chose
    (a log fit would choose them from the whole log, the watcher from its warm-up)."""
    columns = {"t": samples.t[:count], "q": samples.q[:count], "tau": samples.tau[:count]}
    return fit_log(columns, cutoff=watcher.filter.cutoff or 0.0, decimate=watcher.filter.decimation,
                   window=watcher.window, **settings)


@pytest.mark.parametrize("rate, size", [(50.0, 1), (1000.0, 50)])
def test_an_arm_converges_to_its_truth(rate, size):
    samples = arm(rate, 60.0)
    _, refreshes = watched(samples, size)
    final = refreshes[-1][1]
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
    final = refreshes[-1][1]
    assert [trace.name for trace in final.parameters] == ["kA", "kV", "kS"]
    for trace in final.parameters:
        truth = samples.truth[trace.name]
        assert abs(trace.value - truth) <= 0.05 * abs(truth), trace


CASES = [
    pytest.param(lambda: arm(1000.0, 40.0, noise=3.0), 50, {}, {}, id="arm-1kHz"),
    pytest.param(lambda: arm(50.0, 60.0, noise=3.0), 1, {}, {}, id="arm-50Hz"),
    pytest.param(lambda: flywheel(50.0, 60.0, noise=0.6), 1, {"effort": "voltage", "mechanism": "simple"},
                 {"effort": "voltage", "model": "simple"}, id="flywheel-50Hz"),
]


@pytest.mark.parametrize("make, size, settings, fitted_as", CASES)
def test_determination_is_no_earlier_than_an_offline_fit_allows(make, size, settings, fitted_as):
    # Noisy enough that the parameters become determined while the joint moves, not at the first refresh.
    samples = make()
    watcher, refreshes = watched(samples, size, **settings)
    moments = {}
    for count, refresh in refreshes:
        for trace in refresh.parameters:
            if trace.determined_at is not None and trace.name not in moments:
                moments[trace.name] = (count, trace.determined_pct)
    assert moments, "nothing became well determined"
    for name, (count, percent) in moments.items():
        fit = offline(samples, count, watcher, **fitted_as)
        relative = 100 * fit.bse[name] / abs(fit.params[name])
        # The same samples fitted offline determine it too, to about the precision the watcher said (a standard
        # error is itself known to some 10-20 % from a minute of correlated residuals).
        assert relative <= 10.0, (name, count, relative)
        assert relative <= 1.5 * percent, (name, count, relative, percent)


@pytest.mark.parametrize("make, size, settings, fitted_as", [
    pytest.param(lambda: arm(1000.0, 60.0), 50, {}, {}, id="arm-1kHz"),
    pytest.param(lambda: arm(50.0, 60.0), 1, {}, {}, id="arm-50Hz"),
    pytest.param(lambda: flywheel(50.0, 60.0), 1, {"effort": "voltage", "mechanism": "simple"},
                 {"effort": "voltage", "model": "simple"}, id="flywheel-50Hz"),
])
def test_the_last_refresh_matches_an_offline_fit_of_the_same_samples(make, size, settings, fitted_as):
    samples = make()
    watcher, refreshes = watched(samples, size, **settings)
    final = refreshes[-1][1]
    fit = offline(samples, len(samples.t), watcher, **fitted_as)
    # The live fit leaves out each stretch's ends (a stream cannot know the end polynomials) and judges standstill
    # and outside torques block by block: a few percent of the rows differ, so the estimates agree within their
    # standard error and the errors to the precision a standard error has.
    assert final.fitted >= 0.8 * fit.result.training.count
    for trace in final.parameters:
        error = fit.bse[trace.name]
        assert abs(trace.value - fit.params[trace.name]) <= 1.5 * error, (trace, fit.params[trace.name], error)
        assert 0.7 <= trace.error / error <= 1.4, (trace.name, trace.error, error)
    assert final.result.params.keys() == fit.params.keys()
    assert dict(final.result.bse) == {trace.name: trace.error for trace in final.parameters}


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
