"""The live fit does not depend on how its samples were cut into blocks, and its verdicts arrive as an offline fit's
do: the halves of the run are compared with Newey-West errors of each half, as a log fit compares them."""

from __future__ import annotations

import threading
import time

import numpy as np

from jointid.live.growing_csv import GrowingCsv
from jointid.live.received import Received
from jointid.studies.log_fit import fit_log
from jointid.studies.watch import Watcher
from jointid.estimation.uncertainty import WEAK_LIMIT, WELL_DETERMINED_LIMIT
from tests.support.watched_joints import arm


def watched_in(samples, size: int) -> tuple[Watcher, list]:
    """A Watcher fed the samples in blocks of `size`; (the watcher, [refresh before the end, refresh after])."""
    watcher = Watcher()
    for first in range(0, len(samples.t), size):
        rows = slice(first, first + size)
        watcher.add(Received({"t": samples.t[rows], "q": samples.q[rows], "tau": samples.tau[rows]}))
    before = watcher.refresh()
    watcher.add(Received(ended=True))
    return watcher, [before, watcher.refresh()]


def test_the_fit_is_the_same_whatever_blocks_the_samples_came_in():
    # A 50 Hz arm with Coulomb friction: one row at a time, 7, 10 (a logger flushing every 10 lines), 100, or the
    # whole log at once give the same warm-up, the same robust blocks, hence the same rows and estimates.
    samples = arm(50.0, 40.0, noise=0.5)
    runs = {size: watched_in(samples, size)[1] for size in (1, 7, 10, 100, len(samples.t))}
    whole = runs[len(samples.t)]
    for size, refreshes in runs.items():
        for refresh, reference in zip(refreshes, whole):
            assert refresh.fitted == reference.fitted, (size, refresh.fitted, reference.fitted)
            for trace, expected in zip(refresh.parameters, reference.parameters):
                assert trace.value == np.float64(expected.value) or abs(trace.value - expected.value) <= \
                    1e-9 * abs(expected.value), (size, trace.name)
                assert abs(trace.error - expected.error) <= 1e-6 * expected.error, (size, trace.name)
                assert trace.verdict == expected.verdict, (size, trace.name)
    # The end judges the rows that waited for a robust block: the last refresh fits them too.
    assert whole[1].fitted > whole[0].fitted


def test_the_last_refresh_gives_an_offline_fits_verdicts():
    # 40 s at 50 Hz: the halves can be compared long before the end, so the verdicts are an offline fit's of the
    # same samples (with the watcher's filter), for every parameter not within 15 % of a verdict's limit.
    samples = arm(50.0, 40.0, noise=0.5)
    watcher, (_, final) = watched_in(samples, 10)
    fit = fit_log({"t": samples.t, "q": samples.q, "tau": samples.tau}, cutoff=watcher.filter.cutoff,
                  decimate=watcher.filter.decimation, window=watcher.window)
    compared = []
    for trace, name, verdict in zip(final.parameters, fit.result.model.names, fit.result.judgement.verdicts):
        relative = 100 * fit.bse[name] / abs(fit.params[name])
        if min(abs(relative / limit - 1) for limit in (WELL_DETERMINED_LIMIT, WEAK_LIMIT)) < 0.15:
            continue
        assert trace.verdict == verdict, (name, trace, verdict, relative)
        compared.append(verdict)
    assert "well determined" in compared and "weak" in compared and len(compared) >= 3, compared


def test_a_csv_appended_ten_lines_at_a_time_fits_the_rows_read_at_once(tmp_path):
    # A logger writing 10 lines at a time (each line flushed) while the watcher reads: the same rows fitted as
    # the same samples handed over at once.
    samples = arm(50.0, 40.0, noise=0.5)
    lines = [f"{t:.17g},{q:.17g},{tau:.17g}\n" for t, q, tau in zip(samples.t, samples.q, samples.tau)]
    path = tmp_path / "bench.csv"
    path.write_text("t,q,tau\n")
    source = GrowingCsv(path)

    def write():
        with open(path, "a") as handle:
            for first in range(0, len(lines), 10):
                for line in lines[first:first + 10]:
                    handle.write(line)
                    handle.flush()

    writer = threading.Thread(target=write)
    writer.start()
    watcher, received = Watcher(), 0
    deadline = time.monotonic() + 60.0  # only a failing test waits this long
    while received < len(lines) and time.monotonic() < deadline:
        block = source.poll(0.5)
        received += block.count
        watcher.add(block)
    writer.join()
    source.close()
    watcher.add(Received(ended=True))
    refresh = watcher.refresh()
    _, (_, at_once) = watched_in(samples, len(samples.t))
    assert refresh.received == len(lines)
    assert refresh.fitted == at_once.fitted
