"""Benchmark: load one joint of a 6-joint ROS 2 bag and fit it, against the plainest rosbags loop.

Run `PYTHONPATH=. python benchmarks/bench_bag.py [SECONDS] [--keep]` from the repository root. It writes a
ROS 2 bag (sqlite3 storage, the default of `ros2 bag record`) of sensor_msgs/JointState at 1 kHz with six
joints, SECONDS long (default 3600: the issue's 3.6 million messages), under /tmp once (reused while its
name matches; --keep leaves it there), then times, interleaved over ROUNDS rounds:

- ours: `jointid.logs.request.load_joint_log` of one joint (the numpy byte reader, the shared time checks
  and Savitzky-Golay qdd) and `jointid.studies.log_fit.fit_logs`, what `jointid fit --bag B --joint J` does;
- baseline: the plainest loop a user would write with rosbags: AnyReader.messages() on the topic,
  deserialise every message, find the joint's index by name, append its position, velocity and effort
  to three lists. The baseline stops there: it neither checks time, nor differentiates, nor fits, so the
  ratio flatters it.

and then each one's peak traced memory (tracemalloc, in separate runs: tracing slows allocation). Goals
(issue 14): time ratio ours/baseline <= 1.5, memory ratio <= 2.
"""

from __future__ import annotations

import gc
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from common import peak_memory  # noqa: E402  (this folder is first on sys.path)

ROUNDS = 7
RATE = 1000.0
JOINTS = ("base", "shoulder", "elbow", "wrist_1", "wrist_2", "wrist_3")
TARGET = "elbow"
TRUE = (0.8, 0.4, 0.15)
GOAL_TIME, GOAL_MEMORY = 1.5, 2.0


def write_bag(path: Path, seconds: float) -> float:
    """Write the bag; returns seconds taken. Each message is the template's bytes with its stamp and numbers
    patched in (the layout is fixed), which rosbags' serialiser is checked to produce in tests/core/logs/test_bag.py."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    start = time.perf_counter()
    store = get_typestore(Stores.ROS2_HUMBLE)
    types = store.types
    count = int(seconds * RATE)
    t = np.arange(count) / RATE
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)
    qd = 0.7 * 1.3 * np.cos(1.3 * t) + 0.25 * 2.7 * np.cos(2.7 * t)
    qdd = -0.7 * 1.3**2 * np.sin(1.3 * t) - 0.25 * 2.7**2 * np.sin(2.7 * t)
    tau = TRUE[0] * qdd + TRUE[1] * 9.81 * np.cos(q) + TRUE[2] * qd
    template = types["sensor_msgs/msg/JointState"](
        header=types["std_msgs/msg/Header"](stamp=types["builtin_interfaces/msg/Time"](sec=0, nanosec=0),
                                            frame_id=""),
        name=list(JOINTS), position=np.zeros(6), velocity=np.zeros(6), effort=np.zeros(6))
    from jointid.logs.bag import parse_layout

    raw = bytes(store.serialize_cdr(template, "sensor_msgs/msg/JointState"))
    layout = parse_layout(raw, ros1=False)
    block = np.tile(np.frombuffer(raw, dtype=np.uint8), (min(count, 100_000), 1))
    stamps = 1_700_000_000 * 10**9 + np.round(t * 1e9).astype(np.int64)
    j = JOINTS.index(TARGET)
    with Writer(path, version=9, storage_plugin=StoragePlugin.SQLITE3) as writer:
        connection = writer.add_connection("/joint_states", "sensor_msgs/msg/JointState", typestore=store)
        for first in range(0, count, len(block)):
            rows = slice(first, min(first + len(block), count))
            n = rows.stop - rows.start
            part = block[:n]
            part[:, 4:8] = (stamps[rows] // 10**9).astype("<i4").view(np.uint8).reshape(n, 4)
            part[:, 8:12] = (stamps[rows] % 10**9).astype("<u4").view(np.uint8).reshape(n, 4)
            for k, values in enumerate((q, qd, tau)):
                for joint in range(6):
                    column = values[rows] if joint == j else values[rows] * (0.5 + 0.1 * joint)
                    offset = layout.offsets[k] + 8 * joint
                    part[:, offset: offset + 8] = column.astype("<f8").view(np.uint8).reshape(n, 8)
            for i in range(n):
                writer.write(connection, int(stamps[first + i]) + 150_000, part[i].tobytes())
    return time.perf_counter() - start


def ours(path: Path) -> np.ndarray:
    """What `jointid fit --bag PATH --joint elbow` does: load, check, differentiate, fit."""
    from jointid.logs.request import LoadRequest, load_joint_log
    from jointid.studies.log_fit import fit_logs

    return fit_logs(load_joint_log(LoadRequest(str(path), joint=TARGET))).result.estimate


def baseline(path: Path) -> tuple[list, list, list]:
    """The plainest rosbags loop: deserialise every message, append the joint's three numbers."""
    from rosbags.highlevel import AnyReader

    position, velocity, effort = [], [], []
    with AnyReader([path]) as reader:
        connections = [c for c in reader.connections if c.topic == "/joint_states"]
        for connection, _, raw in reader.messages(connections=connections):
            message = reader.deserialize(raw, connection.msgtype)
            i = message.name.index(TARGET)
            position.append(message.position[i])
            velocity.append(message.velocity[i])
            effort.append(message.effort[i])
    return position, velocity, effort


def timed(function, path) -> tuple[float, object]:
    gc.collect()
    start = time.perf_counter()
    result = function(path)
    return time.perf_counter() - start, result


def main(argv: list[str]) -> int:
    seconds = float(next((a for a in argv if not a.startswith("--")), 3600))
    path = Path("/tmp") / f"jointid-bench-bag-{seconds:g}s"
    if not (path / "metadata.yaml").exists():
        import shutil

        shutil.rmtree(path, ignore_errors=True)
        took = write_bag(path, seconds)
        print(f"wrote {path} in {took:.1f} s")
    size = sum(f.stat().st_size for f in path.iterdir())
    print(f"bag: {int(seconds * RATE):,} messages ({seconds:g} s at {RATE:g} Hz, 6 joints), {size / 1e6:.0f} MB, "
          "ROS 2 sqlite3")
    times = {"ours": [], "baseline": []}
    for round_ in range(ROUNDS):
        order = (("ours", ours), ("baseline", baseline)) if round_ % 2 == 0 else (("baseline", baseline), ("ours", ours))
        for name, function in order:
            seconds_taken, result = timed(function, path)
            times[name].append(seconds_taken)
            if name == "ours" and np.max(np.abs(np.asarray(result) / TRUE - 1)) > 1e-3:
                print(f"ours: wrong estimate {result}")
                return 1
    memory = {"ours": peak_memory(ours, path), "baseline": peak_memory(baseline, path)}
    for name in ("ours", "baseline"):
        values = times[name]
        print(f"{name:<9} min {min(values):.2f} s, median {statistics.median(values):.2f} s, max {max(values):.2f} s; "
              f"peak traced memory {memory[name] / 1e6:.0f} MB")
    ratio = min(times["ours"]) / min(times["baseline"])
    median_ratio = statistics.median(times["ours"]) / statistics.median(times["baseline"])
    memory_ratio = memory["ours"] / memory["baseline"]
    print(f"time ratio ours/baseline: {ratio:.2f} (min), {median_ratio:.2f} (median); goal <= {GOAL_TIME}")
    print(f"memory ratio ours/baseline: {memory_ratio:.2f}; goal <= {GOAL_MEMORY}")
    if "--keep" not in argv:
        import shutil

        shutil.rmtree(path, ignore_errors=True)
    return 0 if ratio <= GOAL_TIME and memory_ratio <= GOAL_MEMORY else 1


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
