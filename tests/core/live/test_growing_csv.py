"""A CSV read as it grows: complete lines only, partial lines waited for, truncation and replacement said, the end
found, bad cells named by file, row and column."""

import math
import os
import threading
import time

import numpy as np
import pytest
from support.simulated_joints import arm

from jointid.live.growing_csv import GrowingCsv
from jointid.live.reading import LiveReading
from jointid.logs.conventions import AngleConvention
from jointid.logs.effort import EffortReading
from jointid.logs.table import LogError

HEADER = "time,position,velocity,acceleration,torque\n"


def lines_of(run) -> list[str]:
    """The run's rows as CSV lines at 17 significant digits."""
    return [",".join(f"{v:.17g}" for v in row) + "\n" for row in zip(run.t, run.q, run.qd, run.qdd, run.tau)]


def collect(source, rows: int, timeout: float = 20.0) -> tuple[dict, list]:
    """Poll until `rows` samples have arrived (or the source ends); (columns joined, every block)."""
    blocks = []
    received = 0
    deadline = time.monotonic() + timeout  # only a failing test waits this long
    while received < rows and time.monotonic() < deadline:
        block = source.poll(0.5)
        blocks.append(block)
        received += block.count
        if block.ended:
            break
    names = {name for block in blocks for name in block.columns}
    columns = {name: np.concatenate([b.columns[name] for b in blocks if b.count]) for name in names}
    return columns, blocks


def events_of(blocks) -> list[str]:
    return [event for block in blocks for event in block.events]


def test_rows_appended_by_a_writer_in_odd_pieces_arrive_whole_and_exact(tmp_path):
    run = arm(rate=200, duration=2.0)
    text = (HEADER + "".join(lines_of(run))).encode()
    path = tmp_path / "capture.csv"
    path.write_bytes(b"")
    source = GrowingCsv(path)
    pieces = np.random.default_rng(3).integers(1, 97, size=len(text))
    cuts = np.cumsum(pieces)
    cuts = [0, *cuts[cuts < len(text)].tolist(), len(text)]

    def write():
        with open(path, "ab", buffering=0) as handle:
            for start, end in zip(cuts[:-1], cuts[1:]):
                handle.write(text[start:end])  # mostly pieces of a line: the reader sees many partial lines

    writer = threading.Thread(target=write)
    writer.start()
    columns, blocks = collect(source, len(run.t))
    writer.join()
    source.close()
    for name in ("t", "q", "qd", "qdd", "tau"):
        np.testing.assert_array_equal(columns[name], getattr(run, name))
    assert any("reading" in event and "q=position" in event for event in events_of(blocks))


def test_a_partial_last_line_is_waited_for_not_misread(tmp_path):
    path = tmp_path / "capture.csv"
    path.write_text(HEADER + "0,0.5,1,2,3\n0.01,0.6")
    source = GrowingCsv(path)
    first = source.poll(0.1)
    assert first.count == 1 and first.columns["q"].tolist() == [0.5]
    assert source.poll(0.05).count == 0  # "0.01,0.6" is not a sample (nor q = 0.6 with the rest missing)
    with open(path, "a") as handle:
        handle.write("25,1.5,2.5,3.5\n")
    second = source.poll(1.0)
    assert second.columns["q"].tolist() == [0.625] and second.columns["tau"].tolist() == [3.5]


def test_the_end_is_found_after_an_idle_timeout_and_a_cut_last_line_is_said(tmp_path):
    path = tmp_path / "capture.csv"
    path.write_text(HEADER + "0,0.5,1,2,3\n0.01,0.6,1")
    source = GrowingCsv(path, idle_timeout=0.2)
    blocks = [source.poll(1.0)]
    while not blocks[-1].ended:
        blocks.append(source.poll(1.0))
    assert sum(block.count for block in blocks) == 1
    events = events_of(blocks)
    assert any("line 3 has no line end: left out" in event for event in events)
    assert "no new line in 0.2 s: the writer seems done" in events
    assert source.poll(0.1).ended


def test_a_duration_ends_the_source_at_that_many_seconds_of_samples(tmp_path):
    run = arm(rate=100, duration=3.0)
    path = tmp_path / "capture.csv"
    path.write_text(HEADER + "".join(lines_of(run)))
    source = GrowingCsv(path, duration=1.5)
    columns, blocks = collect(source, len(run.t))
    assert blocks[-1].ended
    np.testing.assert_array_equal(columns["t"], run.t[run.t <= 1.5])


def test_a_truncated_file_is_read_again_as_a_new_stretch_whose_time_follows_on(tmp_path):
    path = tmp_path / "capture.csv"
    path.write_text(HEADER + "0,0.1,0,0,1\n0.01,0.2,0,0,1\n")
    source = GrowingCsv(path)
    assert source.poll(0.5).count == 2
    path.write_text(HEADER + "0,0.3,0,0,1\n")  # the logger started again: same file, shorter
    block = source.poll(1.0)
    while not block.count:
        block = source.poll(1.0)
    assert block.columns["q"].tolist() == [0.3]
    assert block.breaks == (0,)
    assert block.columns["t"][0] > 0.01  # time never runs backwards across a break
    assert any("was truncated" in event for event in block.events)
    assert any("clock started again" in event for event in block.events)


def test_a_file_written_again_past_where_reading_was_is_read_again_not_misread(tmp_path):
    path = tmp_path / "capture.csv"
    path.write_text(HEADER + "0,0.1,0,0,1\n")
    source = GrowingCsv(path)
    assert source.poll(0.5).count == 1
    # The logger started again in the same file and wrote more than before between two polls.
    path.write_text(HEADER + "0,0.25,0,0,1\n0.01,0.35,0,0,1\n0.02,0.45,0,0,1\n")
    columns, blocks = collect(source, 3)
    assert columns["q"].tolist() == [0.25, 0.35, 0.45]
    assert any("was written again from its start" in event for event in events_of(blocks))


def test_a_replaced_file_is_read_out_then_the_new_one_from_its_start(tmp_path):
    path = tmp_path / "capture.csv"
    path.write_text(HEADER + "0,0.1,0,0,1\n")
    source = GrowingCsv(path)
    assert source.poll(0.5).count == 1
    with open(path, "a") as handle:  # the old file's last line, written before the new one took its name
        handle.write("0.01,0.2,0,0,1\n")
    replacement = tmp_path / "new.csv"
    replacement.write_text("time,position,velocity,acceleration,torque\n5,0.7,0,0,2\n5.01,0.8,0,0,2\n")
    os.replace(replacement, path)
    columns, blocks = collect(source, 3)
    assert columns["q"].tolist() == [0.2, 0.7, 0.8]
    assert any("was replaced by a new file" in event for event in events_of(blocks))
    assert any(block.breaks == (0,) and block.columns["q"][0] == 0.7 for block in blocks)


def test_a_file_replaced_by_one_of_other_columns_is_refused(tmp_path):
    path = tmp_path / "capture.csv"
    path.write_text(HEADER + "0,0.1,0,0,1\n")
    source = GrowingCsv(path)
    assert source.poll(0.5).count == 1
    path.write_text("t,q,tau\n")
    with pytest.raises(LogError, match="replaced by a log of other columns"):
        source.poll(1.0)


def test_degrees_the_angle_convention_and_a_current_are_converted_as_a_log_is(tmp_path):
    path = tmp_path / "capture.csv"
    path.write_text("t,q,qd,qdd,tau\n0,90,180,-45,2\n")
    reading = LiveReading(degrees=True, angle=AngleConvention(zero="down", clockwise=True),
                          effort=EffortReading("current", gear=10.0, kt=0.02, efficiency=0.5))
    source = GrowingCsv(path, reading=reading)
    block = source.poll(0.5)
    assert source.effort == "torque"
    # q = -pi/2 - angle (zero down, clockwise); qd, qdd and tau change sign; tau = 10 * 0.02 * 0.5 * 2 A.
    assert block.columns["q"][0] == pytest.approx(-math.pi / 2 - math.pi / 2)
    assert block.columns["qd"][0] == pytest.approx(-math.pi)
    assert block.columns["qdd"][0] == pytest.approx(math.pi / 4)
    assert block.columns["tau"][0] == pytest.approx(-0.2)
    assert any("torque = 0.1 N m/A" in event for event in block.events)


def test_a_state_column_arrives_as_text(tmp_path):
    path = tmp_path / "capture.csv"
    path.write_text("t,q,tau,state\n0,0.1,1,quasistatic-forward\n0.02,0.2,1,none\n")
    block = GrowingCsv(path, reading=LiveReading(effort=EffortReading("voltage"))).poll(0.5)
    assert block.columns["state"].tolist() == ["quasistatic-forward", "none"]


@pytest.mark.parametrize("text, message", [
    ("t,q,qd,qdd,tau\n0,0,0,0,1\n0.01,abc,0,0,1\n", "capture.csv, row 3, column 2 (q): 'abc' is not a number"),
    ("t,q,qd,qdd,tau\n0,0,0,0,1\n0.01,0,0,,1\n", "capture.csv, row 3, column 4 (qdd): is empty"),
    ("t,q,qd,qdd,tau\n0,0,nan,0,1\n", "capture.csv, row 2, column 3 (qd): NaN is not a measurement"),
    ("t,q,qd,qdd,tau\n0,0,0,0,1\n0.01,0,0,1\n", "capture.csv, row 3: has 4 cells but the header has 5 columns"),
    ("t,q,tau\n1,0,1\n0.5,0,1\n", "capture.csv, row 3, column 1 (t): time runs backwards"),
    ("t,qd,qdd,tau\n0,0,0,1\n", "capture.csv, row 1: missing required column 'q' in the header"),
    ("q,qd,qdd,tau\n0,0,0,1\n", "capture.csv, row 1: missing column 't': a log read as it grows needs its times"),
])
def test_bad_input_is_one_line_naming_file_row_and_column(tmp_path, text, message):
    path = tmp_path / "capture.csv"
    path.write_text(text)
    source = GrowingCsv(path)
    with pytest.raises(LogError) as raised:
        for _ in range(3):
            source.poll(0.1)
    assert message in str(raised.value) and "\n" not in str(raised.value)


def test_a_missing_file_or_a_fifo_is_refused_at_once(tmp_path):
    with pytest.raises(LogError, match="cannot open"):
        GrowingCsv(tmp_path / "absent.csv")
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    with pytest.raises(LogError, match="not a regular file"):
        GrowingCsv(fifo)


def test_a_wrapped_angle_is_unwrapped_across_blocks_and_said_once(tmp_path):
    t = np.arange(600) * 0.01
    turning = 4.0 * t + 0.5 * np.sin(2 * t)  # a joint turning round and round
    wrapped = np.angle(np.exp(1j * turning))  # as an encoder reports it, in (-pi, pi]
    path = tmp_path / "capture.csv"
    path.write_text("t,q,tau\n" + "".join(f"{a!r},{b!r},1\n" for a, b in zip(t.tolist(), wrapped.tolist())))
    source = GrowingCsv(path, chunk_bytes=2000)  # many blocks: wraps fall in them and between them
    columns, blocks = collect(source, len(t))
    np.testing.assert_allclose(columns["q"], wrapped[0] + (turning - turning[0]), rtol=0, atol=1e-12)
    assert sum("the angle is wrapped" in event for event in events_of(blocks)) == 1


@pytest.mark.parametrize("text, message", [
    ("", "capture.csv: is empty: no header row came (no new line in 0.1 s: the writer seems done)"),
    ("# rig 3\nt,q,ta", "capture.csv: has no complete header row: no header row came"),
])
def test_a_file_that_ends_without_a_header_is_one_line(tmp_path, text, message):
    path = tmp_path / "capture.csv"
    path.write_text(text)
    source = GrowingCsv(path, idle_timeout=0.1)
    with pytest.raises(LogError) as raised:
        while not source.poll(0.5).ended:
            pass
    assert message in str(raised.value)


def test_crlf_lines_a_byte_order_mark_and_comments_read_as_the_csv_reader_reads_them(tmp_path):
    path = tmp_path / "capture.csv"
    path.write_bytes("\ufeff# rig 3\r\nt,q,qd,qdd,tau\r\n0,0.1,0.2,0.3,1\r\n# note\r\n\r\n0.5,0.2,0.3,0.4,2\r\n"
                     "1,0.3,0.4,0.5,3\r\n".encode())
    columns, _ = collect(GrowingCsv(path), 3)
    assert columns["q"].tolist() == [0.1, 0.2, 0.3] and columns["tau"].tolist() == [1, 2, 3]
    more = tmp_path / "more.csv"
    more.write_bytes(b"t,q,tau\r\n")
    source = GrowingCsv(more)
    assert source.poll(0.5).count == 0  # the header alone: the rows below come in a chunk of their own
    with open(more, "ab") as handle:  # read by numpy's reader, with CRLF and a blank line
        handle.write(b"".join(b"%d,0.%d,1\r\n" % (k, k) for k in range(1, 9)) + b"\r\n9,0.9,1\r\n")
    columns, _ = collect(source, 9)
    assert columns["q"].tolist() == [k / 10 for k in range(1, 10)]


def test_a_bad_cell_after_rows_read_in_bulk_is_named_at_its_own_line(tmp_path):
    path = tmp_path / "capture.csv"
    path.write_text("t,q,tau\n")
    source = GrowingCsv(path)
    source.poll(0.5)
    with open(path, "a") as handle:
        handle.write("".join(f"{k},0.{k},1\n" for k in range(9)) + "\n")
    assert collect(source, 9)[0]["q"].tolist()[-1] == 0.8
    with open(path, "a") as handle:
        handle.write("9,0.9,1\n10,x,1\n")
    with pytest.raises(LogError, match=r"capture.csv, row 13, column 2 \(q\): 'x' is not a number"):
        source.poll(0.5)
