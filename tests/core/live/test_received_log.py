"""The received log: read back by jointid's CSV reader to the very samples received, a gap kept (fitted as rows,
or refused where derivatives would bridge it), written atomically and never over a file unasked."""

import os

import numpy as np
import pytest
from support.simulated_joints import arm, flywheel

from jointid.files import AlreadyExists
from jointid.live.growing_csv import GrowingCsv
from jointid.live.received import Received
from jointid.live.received_log import ReceivedLog
from jointid.logs.csv_reader import load_log
from jointid.logs.effort import EffortReading
from jointid.logs.request import LoadRequest, load_joint_log
from jointid.logs.table import LogError


def blocks_of(run, names, size=37, breaks_at=()):
    """The run's rows in blocks of `size`, a stretch starting at each row of `breaks_at`."""
    columns = run.columns()
    out = []
    for start in range(0, len(run.t), size):
        rows = slice(start, start + size)
        breaks = tuple(row - start for row in breaks_at if start <= row < start + size)
        out.append(Received(columns={name: columns[name][rows] for name in names}, breaks=breaks))
    return out


def test_a_received_arm_reads_back_to_the_same_samples(tmp_path):
    run = arm(rate=200, duration=3.0)
    log = ReceivedLog(tmp_path / "watched.csv", description="a simulated arm")
    log.write(Received(events=("connected to 127.0.0.1:5810",)))
    for block in blocks_of(run, ("t", "q", "qd", "qdd", "tau")):
        log.write(block)
    assert not (tmp_path / "watched.csv").exists()  # only the temporary beside it, until finished
    assert log.finish() == str(tmp_path / "watched.csv")
    read = load_log(tmp_path / "watched.csv")
    for name in ("t", "q", "qd", "qdd", "tau"):
        np.testing.assert_array_equal(getattr(read.data, name), getattr(run, name))
    text = (tmp_path / "watched.csv").read_text()
    assert "# units: t s, q rad, qd rad/s, qdd rad/s^2, tau N m" in text
    assert "# event: connected to 127.0.0.1:5810" in text
    assert [name for name in os.listdir(tmp_path)] == ["watched.csv"]


def test_a_voltage_source_with_a_state_reads_back_with_effort_voltage(tmp_path):
    run = flywheel(rate=1000, duration=2.0)
    path = tmp_path / "flywheel.csv"
    log = ReceivedLog(path, description="a simulated flywheel", effort="voltage")
    for block in blocks_of(run, ("t", "q", "qd", "tau", "state"), size=500):
        log.write(block)
    log.finish()
    text = path.read_text()
    assert "--effort voltage" in text.splitlines()[2] and "tau V (motor voltage)" in text
    read = load_joint_log(LoadRequest(str(path), effort=EffortReading("voltage")))
    np.testing.assert_array_equal(read.data.tau, run.tau)
    assert "state" in read.ignored
    # GrowingCsv reads the state back as it was received.
    back = GrowingCsv(path, reading=None).poll(0.5)
    assert back.columns["state"].tolist() == run.state.tolist()


def test_a_gap_between_stretches_is_kept_fitted_as_rows_with_derivatives_and_refused_without(tmp_path):
    first, second = arm(rate=100, duration=2.0), arm(rate=100, duration=2.0, start=4.0)
    joined = {name: np.concatenate([getattr(first, name), getattr(second, name)])
              for name in ("t", "q", "qd", "qdd", "tau")}
    whole = type(first)(**joined)
    with_derivatives = ReceivedLog(tmp_path / "full.csv", description="arm")
    for block in blocks_of(whole, ("t", "q", "qd", "qdd", "tau"), size=64, breaks_at=(len(first.t),)):
        with_derivatives.write(block)
    with_derivatives.finish()
    read = load_log(tmp_path / "full.csv")
    np.testing.assert_array_equal(read.data.t, joined["t"])  # the gap is kept: 2 s with no row in it
    assert "# stretch 2 starts here" in (tmp_path / "full.csv").read_text()
    angle_only = ReceivedLog(tmp_path / "angle.csv", description="arm")
    for block in blocks_of(whole, ("t", "q", "tau"), size=64, breaks_at=(len(first.t),)):
        angle_only.write(block)
    angle_only.finish()
    with pytest.raises(LogError, match=r"gap in time: 2.01 s between t = 1.99 s and 4 s.*fit the pieces"):
        load_log(tmp_path / "angle.csv")


def test_an_existing_file_is_refused_before_watching_and_replaced_only_with_overwrite(tmp_path):
    path = tmp_path / "watched.csv"
    path.write_text("keep me\n")
    with pytest.raises(AlreadyExists, match="already exists; not overwriting it"):
        ReceivedLog(path, description="arm")
    run = arm(rate=50, duration=1.0)
    log = ReceivedLog(path, description="arm", overwrite=True)
    log.write(blocks_of(run, ("t", "q", "qd", "qdd", "tau"), size=100)[0])
    assert path.read_text() == "keep me\n"  # still, until the log is finished
    log.finish()
    np.testing.assert_array_equal(load_log(path).data.q, run.q)


def test_an_abandoned_or_empty_log_leaves_nothing(tmp_path):
    run = arm(rate=50, duration=1.0)
    log = ReceivedLog(tmp_path / "a.csv", description="arm")
    log.write(blocks_of(run, ("t", "q", "tau"))[0])
    log.abandon()
    empty = ReceivedLog(tmp_path / "b.csv", description="arm")
    with pytest.raises(ValueError, match="nothing was received"):
        empty.finish()
    assert os.listdir(tmp_path) == []


def test_a_growing_csv_watched_to_its_end_is_written_back_as_it_was(tmp_path):
    run = arm(rate=100, duration=2.0)
    capture = tmp_path / "capture.csv"
    capture.write_text("t,q,qd,qdd,tau\n" + "".join(
        ",".join(repr(float(v)) for v in row) + "\n" for row in zip(run.t, run.q, run.qd, run.qdd, run.tau)))
    source = GrowingCsv(capture, idle_timeout=0.1)
    log = ReceivedLog.for_source(tmp_path / "watched.csv", source)
    block = source.poll(1.0)
    while not block.ended:
        log.write(block)
        block = source.poll(1.0)
    log.write(block)
    log.finish()
    read = load_log(tmp_path / "watched.csv")
    for name in ("t", "q", "qd", "qdd", "tau"):
        np.testing.assert_array_equal(getattr(read.data, name), getattr(run, name))


def test_memory_stays_flat_however_many_rows_are_written(tmp_path):
    import tracemalloc

    run = arm(rate=1000, duration=0.1)
    columns = {name: getattr(run, name) for name in ("q", "qd", "qdd", "tau")}

    def block(k):
        return Received(columns={"t": run.t + 0.1 * k, **columns})

    log = ReceivedLog(tmp_path / "long.csv", description="arm")
    tracemalloc.start()
    try:
        for k in range(50):
            log.write(block(k))
        early = tracemalloc.get_traced_memory()[0]
        for k in range(50, 550):  # 50,000 rows more: kept in the file, not in memory
            log.write(block(k))
        late = tracemalloc.get_traced_memory()[0]
    finally:
        tracemalloc.stop()
    log.finish()
    assert late - early < 64 * 1024
    assert load_log(tmp_path / "long.csv").data.count == 55_000
