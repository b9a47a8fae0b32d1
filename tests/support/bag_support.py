"""Writing test bags with rosbags' own writers, from a closed-form model of the joint (not jointid's code).

The first joint follows the rich motion q = 0.7 sin(1.3 t) + 0.25 sin(2.7 t) with
I = 0.8, h = 0.4, B = 0.15 and g = 9.81; its effort is
tau = I qdd + h g cos(q) + B qd plus uniform noise within +-0.05 N m (RMS 0.05/sqrt(3)).
The second joint swings slowly and is there to be skipped.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

TRUE = {"I": 0.8, "h": 0.4, "B": 0.15}
G = 9.81
NOISE_BOUND = 0.05
NOISE_RMS = NOISE_BOUND / np.sqrt(3)
JOINTS = ("shoulder", "elbow")
KINDS = ("sqlite3", "mcap", "ros1")


def rich(t):
    """q, qd, qdd of the rich motion at times t (s)."""
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)
    qd = 0.7 * 1.3 * np.cos(1.3 * t) + 0.25 * 2.7 * np.cos(2.7 * t)
    qdd = -0.7 * 1.3**2 * np.sin(1.3 * t) - 0.25 * 2.7**2 * np.sin(2.7 * t)
    return q, qd, qdd


def jittered_times(duration: float, rate: float, jitter: float = 0.05, seed: int = 1) -> np.ndarray:
    """Sample times from 0 whose steps are 1/rate times (1 + u), u uniform within +-jitter."""
    rng = np.random.default_rng(seed)
    count = int(round(duration * rate))
    steps = (1.0 + jitter * rng.uniform(-1.0, 1.0, count - 1)) / rate
    return np.concatenate(([0.0], np.cumsum(steps)))


def two_joints(t, seed: int = 2):
    """{'shoulder': (q, qd, tau), 'elbow': (q, qd, tau)} at times t: the model above plus bounded noise."""
    rng = np.random.default_rng(seed)
    q, qd, qdd = rich(t)
    tau = TRUE["I"] * qdd + TRUE["h"] * G * np.cos(q) + TRUE["B"] * qd
    tau = tau + rng.uniform(-NOISE_BOUND, NOISE_BOUND, len(t))
    q2 = 0.3 * np.sin(0.5 * t)
    return {"shoulder": (q, qd, tau), "elbow": (q2, 0.15 * np.cos(0.5 * t), 2.0 + q2)}


def typestore(kind: str):
    """rosbags' typestore for the bag kind."""
    from rosbags.typesys import Stores, get_typestore

    return get_typestore(Stores.ROS1_NOETIC if kind == "ros1" else Stores.ROS2_HUMBLE)


def joint_state(store, stamp_ns: int, names, position, velocity, effort, frame_id="base", seq=0):
    """A sensor_msgs/JointState of rosbags' typestore."""
    types = store.types
    time = types["builtin_interfaces/msg/Time"](sec=int(stamp_ns // 1_000_000_000),
                                                nanosec=int(stamp_ns % 1_000_000_000))
    header_type = types["std_msgs/msg/Header"]
    fields = header_type.__dataclass_fields__
    header = header_type(seq=seq, stamp=time, frame_id=frame_id) if "seq" in fields else \
        header_type(stamp=time, frame_id=frame_id)
    as_array = lambda values: np.asarray(values, dtype=np.float64)  # noqa: E731
    return types["sensor_msgs/msg/JointState"](header=header, name=list(names), position=as_array(position),
                                               velocity=as_array(velocity), effort=as_array(effort))


def serialize(store, kind: str, message) -> bytes:
    """The message's bytes as the bag kind stores them."""
    name = "sensor_msgs/msg/JointState"
    return bytes(store.serialize_ros1(message, name) if kind == "ros1" else store.serialize_cdr(message, name))


class BagWriter:
    """A bag of any kind open for writing: add_topic(), write(), then close() (or use `with`)."""

    def __init__(self, path: Path, kind: str):
        from rosbags.rosbag1 import Writer as Writer1
        from rosbags.rosbag2 import StoragePlugin
        from rosbags.rosbag2 import Writer as Writer2

        self.kind, self.store = kind, typestore(kind)
        if kind == "ros1":
            self.writer = Writer1(path)
        else:
            plugin = StoragePlugin.MCAP if kind == "mcap" else StoragePlugin.SQLITE3
            self.writer = Writer2(path, version=9, storage_plugin=plugin)
        self.writer.open()
        self.connections = {}

    def add_topic(self, topic: str, msgtype: str = "sensor_msgs/msg/JointState"):
        """Register a topic; returns its connection."""
        self.connections[topic] = self.writer.add_connection(topic, msgtype, typestore=self.store)
        return self.connections[topic]

    def write(self, topic: str, received_ns: int, data: bytes) -> None:
        """One message's bytes at a receive time."""
        self.writer.write(self.connections[topic], int(received_ns), data)

    def close(self) -> None:
        """Finish the bag."""
        self.writer.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def bag_path(folder: Path, name: str, kind: str) -> Path:
    """name.bag for ROS 1, a folder name-sqlite3/ or name-mcap/ for ROS 2."""
    return folder / (f"{name}.bag" if kind == "ros1" else f"{name}-{kind}")


def write_joint_bag(path: Path, kind: str, t, joints: dict, *, velocity=True, effort=True, start_ns=1_700_000_000
                    * 1_000_000_000, topic="/joint_states", stamps_zero=False, extra_topic=False) -> Path:
    """A bag of JointState messages at times t (s) with each joint's (q, qd, tau); returns its path."""
    names = list(joints)
    with BagWriter(path, kind) as bag:
        bag.add_topic(topic)
        if extra_topic:
            bag.add_topic("/rosout_count", "std_msgs/msg/Int32")
        stamps = start_ns + np.round(np.asarray(t) * 1e9).astype(np.int64)
        for i, stamp in enumerate(stamps):
            q = [joints[n][0][i] for n in names]
            qd = [joints[n][1][i] for n in names] if velocity else []
            tau = [joints[n][2][i] for n in names] if effort else []
            message = joint_state(bag.store, 0 if stamps_zero else int(stamp), names, q, qd, tau, seq=i)
            # Received a little after the stamp, as a recorder would.
            bag.write(topic, int(stamp) + 200_000, serialize(bag.store, kind, message))
    return path


def write_mismatched_bag(folder: Path, kind: str, field: str, length: int) -> Path:
    """A bag of 100 JointState messages naming 'shoulder' and 'elbow', whose message 41 has `length` values in
    `field` ('position', 'velocity' or 'effort') instead of 2; returns its path."""
    store = typestore(kind)
    path = bag_path(folder, f"mismatch-{field}-{length}", kind)
    with BagWriter(path, kind) as bag:
        bag.add_topic("/joint_states")
        for i in range(100):
            arrays = {name: [0.1 * i, 0.2] for name in ("position", "velocity", "effort")}
            if i == 40:
                arrays[field] = [0.3] * length
            message = joint_state(store, (i + 1) * 2_000_000, ["shoulder", "elbow"], arrays["position"],
                                  arrays["velocity"], arrays["effort"])
            bag.write("/joint_states", (i + 1) * 2_000_000, serialize(store, kind, message))
    return path
