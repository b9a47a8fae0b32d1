"""Live sources: how fast a growing CSV is caught up, and how fast NetworkTables values are kept up with.

Run from the repository root: PYTHONPATH=. .venv/bin/python benchmarks/bench_live_sources.py [ROUNDS]

- GrowingCsv catching up a CSV already 200,000 rows long (an arm at 1 kHz, 200 s), polled until every row has
  arrived, against `pandas.read_csv` of the same file (the strongest baseline: a script that reads it once).
  Each round times both, in alternating order; the ratio is ours / pandas'. No goal: a live 1 kHz logger writes
  1,000 rows a second, far below either; the ratio says how long an hour-long capture takes to catch up.
- NetworkTablesSource on loopback: four topics of an arm published with explicit time stamps to an NT4 server
  in this process, for 2 s at 1,000 to 40,000 rows a second, polled every 0.1 s (a watch's refresh), against a
  bare pyntcore client a user would write (generic subscribers with sendAll, readQueue every 0.1 s). Printed:
  the share of rows each received whole and the rows the source counted as dropped. Goal: every row at 1 kHz.
"""

from __future__ import annotations

import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

import ntcore  # noqa: E402
import pandas as pd  # noqa: E402
from support.nt_publishers import LoopbackServer, wait_until  # noqa: E402
from support.simulated_joints import arm  # noqa: E402

from jointid.live.growing_csv import GrowingCsv  # noqa: E402
from jointid.live.network_tables import NetworkTablesSource  # noqa: E402

TOPICS = {"/Arm/Position": "double", "/Arm/Velocity": "double", "/Arm/Acceleration": "double",
          "/Arm/Torque": "double"}
ENTRIES = "q=/Arm/Position,qd=/Arm/Velocity,qdd=/Arm/Acceleration,tau=/Arm/Torque"


def catch_up(path: Path, rows: int) -> float:
    """Seconds GrowingCsv takes to hand over every row of `path`."""
    began = time.perf_counter()
    source = GrowingCsv(path)
    received = 0
    while received < rows:
        received += source.poll(0.0).count
    source.close()
    return time.perf_counter() - began


def read_once(path: Path) -> float:
    """Seconds pandas.read_csv takes to read `path`."""
    began = time.perf_counter()
    pd.read_csv(path)
    return time.perf_counter() - began


def bench_csv(folder: Path, rounds: int) -> None:
    """Print GrowingCsv's catch-up time over pandas.read_csv's."""
    run = arm(rate=1000, duration=200.0)
    path = folder / "capture.csv"
    columns = [run.t, run.q, run.qd, run.qdd, run.tau]
    with open(path, "w") as handle:
        handle.write("t,q,qd,qdd,tau\n")
        handle.writelines(",".join(repr(value) for value in row) + "\n" for row in zip(*(c.tolist() for c in columns)))
    ratios = []
    for round_ in range(rounds):
        if round_ % 2:
            baseline, ours = read_once(path), catch_up(path, len(run.t))
        else:
            ours, baseline = catch_up(path, len(run.t)), read_once(path)
        ratios.append(ours / baseline)
    print(f"GrowingCsv catch-up of {len(run.t)} rows / pandas.read_csv: min {min(ratios):.2f}  median "
          f"{statistics.median(ratios):.2f}  max {max(ratios):.2f}")


def receive_with_source(server: LoopbackServer, run, rate: float) -> tuple[int, int]:
    """(rows received, rows dropped) by NetworkTablesSource polled every 0.1 s while `run` is published."""
    source = NetworkTablesSource(server.address, ENTRIES)
    try:
        wait_until(lambda: all(server.subscribed(name) for name in TOPICS))
        stream = server.stream(dict(zip(TOPICS, (run.q, run.qd, run.qdd, run.tau))), run.t, speedup=rate / 1000)
        received = dropped = 0
        deadline = time.monotonic() + len(run.t) / rate + 3.0
        while received < len(run.t) and time.monotonic() < deadline:
            block = source.poll(0.1)
            received += block.count
            dropped += block.dropped
        stream.join()
        return received, dropped
    finally:
        source.close()


def receive_bare(server: LoopbackServer, run, rate: float) -> int:
    """Rows whose four values a bare pyntcore client (readQueue every 0.1 s) received."""
    client = ntcore.NetworkTableInstance.create()
    options = ntcore.PubSubOptions(sendAll=True, keepDuplicates=True, pollStorage=1 << 20, periodic=0.02)
    subscribers = [client.getTopic(name).genericSubscribe(options) for name in TOPICS]
    client.setServer("127.0.0.1", server.port)
    client.startClient4("bare")
    try:
        wait_until(client.isConnected)
        wait_until(lambda: all(server.subscribed(name) for name in TOPICS))
        stream = server.stream(dict(zip(TOPICS, (run.q, run.qd, run.qdd, run.tau))), run.t, speedup=rate / 1000)
        counts = [0] * len(subscribers)
        deadline = time.monotonic() + len(run.t) / rate + 3.0
        while min(counts) < len(run.t) and time.monotonic() < deadline:
            time.sleep(0.1)  # a refresh's period
            for index, subscriber in enumerate(subscribers):
                counts[index] += sum(1 for value in subscriber.readQueue() if value.value() is not None)
        stream.join()
        return min(counts)
    finally:
        ntcore.NetworkTableInstance.destroy(client)


def bench_network_tables(folder: Path) -> None:
    """Print the share of rows received at each publishing rate, by the source and by a bare client."""
    for rate in (1000, 5000, 20000, 40000):
        run = arm(rate=rate, duration=2.0)
        server = LoopbackServer(folder)
        server.publish_topics(TOPICS)
        try:
            received, dropped = receive_with_source(server, run, rate)
        finally:
            server.stop()
        server = LoopbackServer(folder)
        server.publish_topics(TOPICS)
        try:
            bare = receive_bare(server, run, rate)
        finally:
            server.stop()
        print(f"NT4 at {rate:>6} rows/s x 4 topics: source {received / len(run.t):7.2%} of rows ({dropped} dropped), "
              f"bare readQueue client {bare / len(run.t):7.2%}")


def main() -> None:
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    with tempfile.TemporaryDirectory() as folder:
        bench_csv(Path(folder), rounds)
        bench_network_tables(Path(folder))


if __name__ == "__main__":
    main()
