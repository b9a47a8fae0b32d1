"""Reading one joint's entries from a large WPILib data log, against the plainest loop over DataLogReader.

Run from the repository root: PYTHONPATH=. .venv/bin/python benchmarks/bench_wpilog_read.py [ROUNDS [MINUTES]]

It writes a robot's log to a temporary directory: MINUTES (default 60) of 200
double entries at 250 Hz (180 million records, 2.7 GB for an hour), among them
/Arm/Position (in radians), /Arm/Velocity and /Arm/Voltage. The records are
encoded with numpy as the format (allwpilib's datalog.adoc) lays them out (a
1-byte entry id, a 1-byte size and a 4-byte time stamp each), so that writing
an hour takes a minute rather than hours of DataLogWriter calls from Python;
robotpy-wpiutil's reader then reads it like any other log.

Each round, in alternating order:

1. jointid: `jointid.logs.wpilog.read_wpilog_table` with the entry map
   q=/Arm/Position,qd=/Arm/Velocity,tau=/Arm/Voltage: the joint's table, on
   the position's time base, in radians, checked.
2. The baseline: the plainest loop a user would write over
   `wpiutil.log.DataLogReader`, collecting those three entries' time stamps
   and values in lists (BASELINE below).

It prints min / median / max of the per-round ratio jointid / baseline and
whether the median meets the goal (1.5), and exits 1 if not.
"""

from __future__ import annotations

import gc
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from jointid.logs.conventions import EntryMap  # noqa: E402
from jointid.logs.wpilog import read_wpilog_table  # noqa: E402

ROUNDS = 3
MINUTES = 60.0
RATE = 250
ENTRIES = 200
GOAL = 1.5
JOINT = ("/Arm/Position", "/Arm/Velocity", "/Arm/Voltage")
CHUNK_LOOPS = 15_000
"""Loop iterations encoded at a time (a minute at 250 Hz: 45 MB)."""


def baseline(path: str, names=JOINT) -> dict:
    """The plainest loop over DataLogReader that collects the named entries' time stamps and values."""
    from wpiutil.log import DataLogReader

    wanted = {name: ([], []) for name in names}
    by_id = {}
    for record in DataLogReader(path):
        if record.isStart():
            data = record.getStartData()
            if data.name in wanted:
                by_id[data.entry] = wanted[data.name]
        elif not record.isControl():
            found = by_id.get(record.getEntry())
            if found is not None:
                found[0].append(record.getTimestamp())
                found[1].append(record.getDouble())
    return wanted


def _start_record(entry: int, name: str, kind: str, metadata: str) -> bytes:
    """A Start control record (entry 0) for `entry`, at time 0."""
    payload = bytearray([0]) + entry.to_bytes(4, "little")
    for text in (name, kind, metadata):
        data = text.encode()
        payload += len(data).to_bytes(4, "little") + data
    return bytes([0x30, 0, len(payload)]) + (0).to_bytes(4, "little") + bytes(payload)


RECORD = np.dtype([("lengths", "u1"), ("entry", "u1"), ("size", "u1"), ("stamp", "<u4"), ("value", "<f8")])
"""One double record: entry id and size in a byte each, a 4-byte time stamp (header byte 0x30 says so)."""


def write_robot_log(path: Path, minutes: float) -> int:
    """Write the log; its record count."""
    names = [*JOINT, *(f"/Robot/Signal{k:03d}" for k in range(ENTRIES - len(JOINT)))]
    units = {"/Arm/Position": "Radian", "/Arm/Velocity": "Radian per Second", "/Arm/Voltage": "Volt"}
    loops = int(minutes * 60 * RATE)
    records = 0
    with open(path, "wb") as handle:
        handle.write(b"WPILOG" + bytes([0, 1]) + (0).to_bytes(4, "little"))
        for k, name in enumerate(names, start=1):
            handle.write(_start_record(k, name, "double", units.get(name, "")))
        ids = np.arange(1, ENTRIES + 1, dtype=np.uint8)
        for first in range(0, loops, CHUNK_LOOPS):
            count = min(CHUNK_LOOPS, loops - first)
            loop = np.arange(first, first + count)
            t = (1_000_000 + loop * (1_000_000 // RATE)).astype(np.uint32)
            block = np.empty((count, ENTRIES), dtype=RECORD)
            block["lengths"], block["size"] = 0x30, 8
            block["entry"] = ids[None, :]
            block["stamp"] = t[:, None] + np.arange(ENTRIES, dtype=np.uint32)[None, :]  # a microsecond apart
            seconds = loop / RATE
            block["value"] = np.sin(0.01 * seconds)[:, None] * (1 + np.arange(ENTRIES))[None, :]
            block["value"][:, 0] = 0.8 * np.sin(1.3 * seconds)
            block["value"][:, 1] = 0.8 * 1.3 * np.cos(1.3 * seconds)
            block["value"][:, 2] = 2.0 * np.sin(1.3 * seconds + 0.3)
            handle.write(block.tobytes())
            records += block.size
    return records


def time_jointid(path: str) -> tuple[float, int]:
    """Seconds to read the joint's table, and its samples."""
    entries = EntryMap.parse(f"q={JOINT[0]},qd={JOINT[1]},tau={JOINT[2]}")
    gc.collect()
    start = time.perf_counter()
    table = read_wpilog_table(path, entries)
    return time.perf_counter() - start, table.count


def time_baseline(path: str) -> tuple[float, int]:
    """Seconds of the baseline loop, and the position entry's records."""
    gc.collect()
    start = time.perf_counter()
    found = baseline(path)
    return time.perf_counter() - start, len(found[JOINT[0]][0])


def main() -> int:
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else ROUNDS
    minutes = float(sys.argv[2]) if len(sys.argv) > 2 else MINUTES
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "robot.wpilog"
        start = time.perf_counter()
        records = write_robot_log(path, minutes)
        print(f"wrote {records:,} records ({path.stat().st_size / 1e9:.2f} GB, {minutes:g} min at {RATE} Hz, "
              f"{ENTRIES} entries) in {time.perf_counter() - start:.0f} s", flush=True)
        ratios = []
        for round_number in range(rounds):
            order = (time_jointid, time_baseline) if round_number % 2 == 0 else (time_baseline, time_jointid)
            results = {function: function(str(path)) for function in order}
            (ours, samples), (plain, collected) = results[time_jointid], results[time_baseline]
            assert samples == collected, (samples, collected)
            ratios.append(ours / plain)
            print(f"round {round_number + 1}: jointid {ours:.1f} s, baseline {plain:.1f} s, ratio {ratios[-1]:.3f}",
                  flush=True)
    median = statistics.median(ratios)
    print(f"read one joint's entries / plainest DataLogReader loop: min {min(ratios):.3f}, median {median:.3f}, "
          f"max {max(ratios):.3f} (goal <= {GOAL}: {'met' if median <= GOAL else 'MISSED'})")
    return 0 if median <= GOAL else 1


if __name__ == "__main__":
    sys.exit(main())
