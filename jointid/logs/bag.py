"""Read a joint from a ROS bag (sensor_msgs/JointState), checked like a CSV log.

ROS 1 `.bag` files, ROS 2 bag folders (sqlite3 or MCAP storage) and single
`.db3`/`.mcap` files are opened with `rosbags` (the optional extra
`jointid[ros]`, imported only here and only when a bag is opened).

Speed: rather than deserialising every message into Python objects, the
JointState bytes are read with numpy. Consecutive messages of one topic almost
always share a layout (the same frame_id, joint names and array lengths, so the
same byte length); they are gathered in blocks, every message of a block is
checked byte for byte against the first outside its stamp and numbers, and the
joint's doubles are then sliced out of the whole block at once. A message that
differs is read on its own. tests/core/logs/test_bag.py checks this against rosbags'
deserialiser on random messages.

Time is header.stamp, or the bag's receive time when every stamp is zero.
Messages out of stamp order are sorted (and a note says so); repeated stamps
go to the shared time checks (jointid.logs.timing) like a CSV log's. Every message is matched by joint name.
"""

from __future__ import annotations

import dataclasses
import os
import struct
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .pipeline import check_finite
from .table import LoadCancelled, LogError, LogTable

JOINT_STATE = "sensor_msgs/msg/JointState"
"""The message type read, as rosbags names it for ROS 1 and ROS 2 alike."""

DEFAULT_TOPIC = "/joint_states"
"""The topic chosen when a bag has several JointState topics and --topic is not given."""

FIELDS = ("position", "velocity", "effort")
"""JointState's numeric arrays, in message order."""

BAG_SUFFIXES = (".bag", ".mcap", ".db3")
"""File endings of bags: ROS 1, and ROS 2 storage files opened on their own."""

EXTRA_HINT = "reading ROS bags needs the optional rosbags package: pip install 'jointid[ros]'"
"""The one line shown when rosbags is not installed."""

BLOCK = 8192
"""Messages gathered before their numbers are sliced out together (about 2 MB for six joints)."""

ProgressCallback = Callable[[int, int], None]
"""progress(messages_read, total_messages)."""

CancelCheck = Callable[[], bool]
"""cancel() -> True to stop reading (raises LoadCancelled)."""


def looks_like_bag(path) -> bool:
    """True for a ROS 2 bag folder (it holds metadata.yaml) or a file ending in .bag, .mcap or .db3."""
    path = os.fspath(path)
    if os.path.isdir(path):
        return os.path.exists(os.path.join(path, "metadata.yaml"))
    return path.lower().endswith(BAG_SUFFIXES)


# ---------------------------------------------------------------------------------------------- layouts


@dataclass(frozen=True, eq=False)
class Layout:
    """Where a JointState message keeps its stamp, joint names and numbers."""

    size: int
    """Bytes in the message."""
    names: tuple[str, ...]
    """Joint names, in message order."""
    stamp: int
    """Offset of header.stamp (int32 seconds, then uint32 nanoseconds)."""
    counts: tuple[int, int, int]
    """Number of values in position, velocity, effort."""
    offsets: tuple[int, int, int]
    """Offset of the first double of each array (-1 when it is empty)."""
    endian: str
    """'<' or '>'."""
    fixed: np.ndarray
    """Indices of the bytes every message of this layout shares (all but the stamp, seq and numbers)."""
    template: np.ndarray
    """The message the layout was read from, as uint8."""

    def filled(self, index: int) -> tuple[bool, bool, bool]:
        """Whether position, velocity and effort hold a value for the joint at `index`."""
        return tuple(count == len(self.names) and count > index for count in self.counts)


class _Truncated(Exception):
    """A message shorter than its own lengths say."""


def parse_layout(raw, ros1: bool) -> Layout:
    """The layout of one serialised JointState (ROS 1 or CDR); _Truncated or ValueError if it is not one."""
    data = bytes(raw)
    size = len(data)
    if ros1:
        endian, base, stamp, position = "<", 0, 4, 12
    else:
        if size < 4 or data[0] != 0 or data[1] not in (0, 1):
            raise ValueError("not CDR-encoded")
        endian, base, stamp, position = ("<" if data[1] == 1 else ">"), 4, 4, 12
    u32 = struct.Struct(endian + "I")

    def align(offset: int, width: int) -> int:
        return offset if ros1 else offset + (-(offset - base)) % width

    def number(offset: int) -> int:
        if offset + 4 > size:
            raise _Truncated
        return u32.unpack_from(data, offset)[0]

    p = position
    p += 4 + number(p)  # frame_id
    p = align(p, 4)
    count = number(p)
    if count > size:
        raise _Truncated
    p += 4
    names = []
    for _ in range(count):
        p = align(p, 4)
        length = number(p)
        p += 4
        text = data[p: p + length]
        names.append(text.rstrip(b"\x00").decode("utf-8", errors="replace") if not ros1 else
                     text.decode("utf-8", errors="replace"))
        p += length
    counts, offsets, varying = [], [], [(stamp, stamp + 8)] + ([(0, 4)] if ros1 else [])
    for _ in FIELDS:
        p = align(p, 4)
        values = number(p)
        p += 4
        if values:
            p = align(p, 8)
            offsets.append(p)
            varying.append((p, p + 8 * values))
            p += 8 * values
        else:
            offsets.append(-1)
        counts.append(values)
    if p > size:
        raise _Truncated
    mask = np.ones(size, dtype=bool)
    for start, end in varying:
        mask[start:end] = False
    return Layout(size, tuple(names), stamp, tuple(counts), tuple(offsets), endian,
                  np.flatnonzero(mask), np.frombuffer(data, dtype=np.uint8))


def doubles(block: np.ndarray, offset: int, endian: str) -> np.ndarray:
    """(n,) float64: the double at `offset` in every row of a (n, size) uint8 block."""
    return np.ascontiguousarray(block[:, offset: offset + 8]).view(endian + "f8")[:, 0].astype(np.float64)


def stamps(block: np.ndarray, layout: Layout) -> np.ndarray:
    """(n,) int64 nanoseconds of header.stamp in every row of a block."""
    s = layout.stamp
    seconds = np.ascontiguousarray(block[:, s: s + 4]).view(layout.endian + "i4")[:, 0].astype(np.int64)
    nanoseconds = np.ascontiguousarray(block[:, s + 4: s + 8]).view(layout.endian + "u4")[:, 0].astype(np.int64)
    return seconds * 1_000_000_000 + nanoseconds


# ---------------------------------------------------------------------------------------------- opening


def _rosbags_reader():
    """rosbags.highlevel.AnyReader, imported now; LogError-ready ImportError text if missing."""
    try:
        from rosbags.highlevel import AnyReader
    except ImportError:
        return None
    return AnyReader


def open_bag(path):
    """An opened rosbags AnyReader (use it as a context manager's result); LogError when it cannot be."""
    path = os.fspath(path)
    if not path.strip():
        raise LogError("(no file)", "cannot open: the path is empty; give a ROS bag's path")
    reader_class = _rosbags_reader()
    if reader_class is None:
        raise LogError(path, EXTRA_HINT)
    if not os.path.exists(path):
        raise LogError(path, "cannot open: No such file or directory")
    if os.path.isdir(path) and not os.path.exists(os.path.join(path, "metadata.yaml")):
        raise LogError(path, "is a folder without metadata.yaml: not a ROS 2 bag folder")
    _check_bag_files(path)
    _check_storage_files(path)
    from pathlib import Path

    try:
        reader = reader_class([Path(path)])
        reader.open()
    except Exception as error:  # rosbags raises many kinds for a damaged file; all mean the same here
        raise LogError(path, _unopenable(path, error)) from None
    return reader


def _bag_kind(path: str) -> str:
    """What the path should hold, in the words of a message: 'a ROS 1 bag', 'an MCAP file', ..."""
    if os.path.isdir(path):
        return "a ROS 2 bag folder"
    return {".bag": "a ROS 1 bag", ".mcap": "an MCAP bag file", ".db3": "an SQLite bag file"}.get(
        os.path.splitext(path)[1].lower(), "a ROS bag")


def _unopenable(path: str, error: BaseException) -> str:
    """jointid's one line for a bag rosbags could not open; rosbags' own text is only used to tell which part
    of a ROS 2 folder is at fault, never shown, since it names internals (offsets, YAML parser states)."""
    kind = _bag_kind(path)
    if os.path.isdir(path):
        if "metadata" in str(error).lower() or "yaml" in str(error).lower():
            return f"cannot be read as {kind}: its metadata.yaml is damaged or not a bag's description"
        return f"cannot be read as {kind}: {_storage_words(path)} damaged, truncated or not a bag's"
    return f"cannot be read as {kind}: the file is damaged, truncated or not a bag"


def storage_files(path: str) -> list[str] | None:
    """The storage files a ROS 2 bag folder's metadata.yaml names (bare names, as rosbags looks them up in the
    folder), or None when it cannot say; read with ruamel.yaml, which rosbags itself reads it with."""
    try:
        from ruamel.yaml import YAML

        from ..files import read_bytes

        text = read_bytes(os.path.join(path, "metadata.yaml"), 1 << 20).decode("utf-8")
        names = YAML(typ="safe").load(text)["rosbag2_bagfile_information"]["relative_file_paths"]
        return [os.path.basename(str(name)) for name in names]
    except Exception:  # noqa: BLE001 - no or damaged metadata: rosbags' open says so, in jointid's words
        return None


def _storage_words(path: str) -> str:
    """'its storage file run_0.mcap is' (named, so the user knows which file to look at), or the files in general."""
    from ..files import shown_path

    names = storage_files(path)
    if not names:
        return "its storage file is"
    if len(names) == 1:
        return f"its storage file {shown_path(names[0])} is"
    return f"one of its storage files ({', '.join(shown_path(name) for name in names)}) is"


def _check_storage_files(path: str) -> None:
    """LogError naming a storage file that metadata.yaml lists but the folder lacks, or that is no regular file
    (a folder in its place): rosbags' own message for these names its internals."""
    if not os.path.isdir(path):
        return
    from ..files import FileRefused, check_readable, shown_path

    for name in storage_files(path) or ():
        file = os.path.join(path, name)
        if not os.path.lexists(file):
            raise LogError(path, f"cannot be read as a ROS 2 bag folder: its storage file {shown_path(name)}, "
                                 "named in metadata.yaml, is missing")
        try:
            check_readable(file)
        except FileRefused as error:
            raise LogError(path, error.problem, place=f"storage file {shown_path(name)}") from None


def _check_bag_files(path: str) -> None:
    """LogError unless every file rosbags may open for this bag is a regular file (jointid.files.check_readable).

    rosbags and sqlite open the paths themselves, and a FIFO among them would block that open for ever. A ROS 2
    folder's metadata.yaml names its storage files; rather than read it before rosbags does, every entry of the
    folder that is not a folder is checked: a bag folder holds nothing else.
    """
    from ..files import FileRefused, check_readable, shown_path

    if os.path.isdir(path):
        try:
            files = sorted(entry.path for entry in os.scandir(path) if not entry.is_dir())
        except OSError as error:
            raise LogError(path, f"cannot open: {error.strerror or error}") from None
    else:
        files = [path]
    for name in files:
        try:
            check_readable(name)
        except FileRefused as error:
            place = None if name == path else f"file {shown_path(os.path.basename(name))}"
            raise LogError(path, error.problem, place=place) from None


def joint_state_topics(reader) -> dict[str, list]:
    """Topic -> its connections, for every JointState topic of an open bag."""
    topics: dict[str, list] = {}
    for connection in reader.connections:
        if connection.msgtype == JOINT_STATE:
            topics.setdefault(connection.topic, []).append(connection)
    return topics


def _is_ros1(reader) -> bool:
    return not reader.is2


# ---------------------------------------------------------------------------------------------- scanning


class _Scan:
    """Reads one topic's messages in blocks of one layout and hands each block to `consume`.

    consume(layout, block, received, numbers): block is (n, size) uint8, received the
    bag's receive times (int64 ns), numbers the 0-based message numbers in the topic.
    """

    def __init__(self, path, reader, connections, consume, progress=None, cancel=None, limit=None):
        self.path, self.reader, self.connections = path, reader, connections
        self.consume, self.progress, self.cancel, self.limit = consume, progress, cancel, limit
        self.ros1 = _is_ros1(reader)
        self.mismatched = 0
        """Messages whose position, velocity or effort array is neither empty nor one value per joint name:
        left out, since no value of theirs can be told to belong to a joint."""
        self.first_mismatch: tuple[int, str] | None = None
        """(0-based message number, what is wrong) of the first such message."""
        self.total = sum(c.msgcount for c in connections)
        if limit is not None:
            self.total = min(self.total, limit)

    def run(self) -> int:
        """Read every message (or the first `limit`); return how many were read."""
        batch, received = [], []
        size, number, first = -1, 0, 0
        try:
            for _, time, raw in self.reader.messages(connections=self.connections):
                if len(raw) != size or len(batch) == BLOCK:
                    if batch:
                        self._flush(batch, received, first)
                        batch, received = [], []
                    size, first = len(raw), number
                batch.append(raw)
                received.append(time)
                number += 1
                if self.limit is not None and number >= self.limit:
                    break
            if batch:
                self._flush(batch, received, first)
        except (LoadCancelled, LogError):
            raise
        except Exception:  # a damaged chunk or table part-way through; rosbags' text names its internals
            topic = self.connections[0].topic
            where = f"after message {number} on {topic}" if number else f"at the first message on {topic}"
            damaged = (f"{_storage_words(self.path)} damaged or truncated there" if os.path.isdir(self.path)
                       else "the bag is damaged or truncated there")
            raise LogError(self.path, f"cannot be read {where}: {damaged}") from None
        return number

    def _flush(self, batch, received, first) -> None:
        if self.cancel is not None and self.cancel():
            raise LoadCancelled(self.path)
        block = np.frombuffer(b"".join(batch), dtype=np.uint8).reshape(len(batch), -1)
        times = np.asarray(received, dtype=np.int64)
        layout = self._layout(batch[0], first)
        same = (block[:, layout.fixed] == layout.template[layout.fixed]).all(axis=1)
        if same.all():
            self._consume(layout, block, times, np.arange(first, first + len(batch)))
        else:  # rare: messages of one length but other names or frame_id; read them one by one
            for i in range(len(batch)):
                own = layout if same[i] else self._layout(batch[i], first + i)
                self._consume(own, block[i: i + 1], times[i: i + 1], np.array([first + i]))
        if self.progress is not None:
            self.progress(first + len(batch), self.total)

    def _consume(self, layout: Layout, block, times, numbers) -> None:
        """Hand messages of a readable layout on; count those whose arrays do not match their names."""
        problem = mismatch(layout)
        if problem is None:
            self.consume(layout, block, times, numbers)
            return
        if self.first_mismatch is None:
            self.first_mismatch = (int(numbers[0]), problem)
        self.mismatched += len(block)
        skipped = getattr(self.consume, "skipped", None)
        if skipped is not None:  # the survey still times them: their stamps are as good as any
            skipped(layout, block, times)

    def mismatch_text(self, read: int) -> str | None:
        """'1 of 100 messages on /joint_states (first: message 41, effort has 3 values for 2 joint names)', or
        None when every message's arrays match its names."""
        if self.first_mismatch is None:
            return None
        number, problem = self.first_mismatch
        return (f"{self.mismatched:,} of {read:,} messages on {self.connections[0].topic} "
                f"(first: message {number + 1}, {problem})")

    def _layout(self, raw, number: int) -> Layout:
        where = f"message {number + 1} on {self.connections[0].topic}"
        try:
            return parse_layout(raw, self.ros1)
        except (_Truncated, ValueError, struct.error):
            raise LogError(self.path, f"{where} cannot be read as sensor_msgs/JointState (damaged or truncated)"
                           ) from None


def mismatch(layout: Layout) -> str | None:
    """What is wrong with a message's array lengths ('effort has 3 values for 2 joint names'), or None.

    ROS gives one value per joint name or none; any other length cannot say which joint a value is.
    """
    joints = len(layout.names)
    for name, count in zip(FIELDS, layout.counts):
        if count not in (0, joints):
            return f"{name} has {count} value{'s' if count != 1 else ''} for {joints} joint name{'s' if joints != 1 else ''}"
    return None


# ---------------------------------------------------------------------------------------------- bag-info


@dataclass
class JointFields:
    """How often one joint appears in a JointState topic and which of its fields are filled."""

    name: str
    messages: int = 0
    filled: dict = field(default_factory=lambda: dict.fromkeys(FIELDS, 0))

    def fields_text(self) -> str:
        """'position, velocity, effort', with '(k of n)' after a field filled only sometimes; 'none'."""
        parts = []
        for name in FIELDS:
            count = self.filled[name]
            if count == self.messages and count:
                parts.append(name)
            elif count:
                parts.append(f"{name} ({count} of {self.messages})")
        return ", ".join(parts) or "none"

    def to_dict(self) -> dict:
        """JSON-ready counts."""
        return {"name": self.name, "messages": self.messages, "filled": dict(self.filled)}


@dataclass
class JointStateTopic:
    """One JointState topic: its joints, message count and timing."""

    name: str
    messages: int
    joints: list[JointFields]
    time_source: str
    """'header.stamp' or 'receive time' (when every stamp is zero)."""
    duration: float
    """Seconds from the first to the last message."""
    median_step: float | None
    max_step: float | None
    min_step: float | None
    mismatched: int = 0
    """Messages whose arrays have other lengths than their joint names (left out of the joints' counts)."""
    first_mismatch: tuple[int, str] | None = None
    """(1-based message number, what is wrong) of the first of them; None when there are none."""

    @property
    def rate(self) -> float | None:
        """Messages per second at the median step."""
        return None if not self.median_step else 1.0 / self.median_step

    @property
    def jitter(self) -> float | None:
        """Largest relative departure of a step from the median step."""
        if not self.median_step:
            return None
        return max(abs(self.max_step - self.median_step), abs(self.median_step - self.min_step)) / self.median_step

    def to_dict(self) -> dict:
        """JSON-ready values."""
        return {
            "topic": self.name, "messages": self.messages, "time_source": self.time_source,
            "duration_s": self.duration, "rate_hz": self.rate, "median_step_s": self.median_step,
            "max_step_s": self.max_step, "min_step_s": self.min_step, "jitter": self.jitter,
            "joints": [j.to_dict() for j in self.joints],
            "mismatched_arrays": None if self.first_mismatch is None else {
                "messages": self.mismatched, "first_message": self.first_mismatch[0],
                "problem": self.first_mismatch[1]},
        }


@dataclass
class BagInfo:
    """What `jointid bag-info` shows: every topic, and the joints of each JointState topic."""

    path: str
    kind: str
    """'ROS 1' or 'ROS 2'."""
    duration: float
    topics: list[tuple[str, str, int]]
    """(topic, message type, count) for every topic."""
    joint_states: list[JointStateTopic]

    def to_dict(self) -> dict:
        """The JSON document of `bag-info --json`."""
        return {
            "path": self.path, "format": self.kind, "duration_s": self.duration,
            "topics": [{"topic": t, "type": m, "messages": n} for t, m, n in self.topics],
            "joint_states": [j.to_dict() for j in self.joint_states],
        }


class _Survey:
    """Collects joints, filled fields and stamps of one topic, block by block."""

    def __init__(self):
        self.joints: dict[str, JointFields] = {}
        self.stamps, self.received = [], []

    def __call__(self, layout, block, received, numbers):
        n = len(block)
        for index, name in enumerate(layout.names):
            joint = self.joints.setdefault(name, JointFields(name))
            joint.messages += n
            for fname, filled in zip(FIELDS, layout.filled(index)):
                joint.filled[fname] += n if filled else 0
        self.stamps.append(stamps(block, layout))
        self.received.append(received)

    def skipped(self, layout, block, received):
        """Messages left out for their array lengths: their times still count for the topic's timing."""
        self.stamps.append(stamps(block, layout))
        self.received.append(received)


def bag_info(path, *, limit: int | None = None, progress=None, cancel=None) -> BagInfo:
    """Survey a bag (the first `limit` messages of each JointState topic, or all); LogError if unreadable."""
    path = os.fspath(path)
    reader = open_bag(path)
    try:
        topics = [(name, info.msgtype or "?", info.msgcount) for name, info in sorted(reader.topics.items())]
        joint_states = []
        for topic, connections in sorted(joint_state_topics(reader).items()):
            survey = _Survey()
            scan = _Scan(path, reader, connections, survey, progress, cancel, limit)
            count = scan.run()
            times, source = _times(np.concatenate(survey.stamps) if survey.stamps else np.zeros(0, np.int64),
                                   np.concatenate(survey.received) if survey.received else np.zeros(0, np.int64))
            times = np.sort(times)
            steps = np.diff(times) * 1e-9
            joint_states.append(JointStateTopic(
                topic, count, list(survey.joints.values()), source,
                float((times[-1] - times[0]) * 1e-9) if count else 0.0,
                float(np.median(steps)) if len(steps) else None,
                float(steps.max()) if len(steps) else None,
                float(steps.min()) if len(steps) else None,
                scan.mismatched,
                None if scan.first_mismatch is None else (scan.first_mismatch[0] + 1, scan.first_mismatch[1]),
            ))
        duration = reader.duration * 1e-9 if reader.message_count else 0.0
        return BagInfo(path, "ROS 1" if _is_ros1(reader) else "ROS 2", duration, topics, joint_states)
    finally:
        reader.close()


def _times(header: np.ndarray, received: np.ndarray) -> tuple[np.ndarray, str]:
    """header.stamp, or the receive times when every stamp is zero; and which it was."""
    if len(header) and not header.any():
        return received, "receive time"
    return header, "header.stamp"


# ---------------------------------------------------------------------------------------------- one joint


class _JointColumns:
    """Collects one joint's stamps and numbers, block by block, into growing arrays."""

    def __init__(self, joint: str, capacity: int):
        self.joint = joint
        self.capacity = max(capacity, 1)
        self.values = np.empty((3, self.capacity))  # q, qd, tau
        self.times = np.empty((3, self.capacity), dtype=np.int64)  # stamp, received, message number
        self.filled = np.empty((3, self.capacity), dtype=bool)
        self.count = 0
        self.messages = 0
        self.names_seen: dict[str, None] = {}
        self.ambiguous: int | None = None

    def __call__(self, layout, block, received, numbers):
        self.messages += len(block)
        try:
            index = layout.names.index(self.joint)
        except ValueError:
            for name in layout.names:
                self.names_seen.setdefault(name)
            return
        if layout.names.count(self.joint) > 1 and self.ambiguous is None:
            self.ambiguous = int(numbers[0])
        n = len(block)
        end = self.count + n
        if end > self.capacity:
            self._grow(end)
        rows = slice(self.count, end)
        filled = layout.filled(index)
        for k, (ok, offset) in enumerate(zip(filled, layout.offsets)):
            self.filled[k, rows] = ok
            self.values[k, rows] = doubles(block, offset + 8 * index, layout.endian) if ok else np.nan
        self.times[0, rows] = stamps(block, layout)
        self.times[1, rows] = received
        self.times[2, rows] = numbers
        self.count = end

    def _grow(self, needed: int) -> None:
        capacity = max(needed, int(self.capacity * 1.5))
        for name in ("values", "times", "filled"):
            old = getattr(self, name)
            new = np.empty((old.shape[0], capacity), dtype=old.dtype)
            new[:, : self.count] = old[:, : self.count]
            setattr(self, name, new)
        self.capacity = capacity


@dataclass(frozen=True, eq=False)
class BagTable(LogTable):
    """One joint's samples from a bag, as a LogTable; messages name the bag message rather than a line."""

    topic: str = DEFAULT_TOPIC
    joint: str = ""
    message_numbers: np.ndarray | None = None
    """0-based number in the topic of each sample's message."""

    @property
    def origin(self) -> dict:
        """LogTable.origin with format "rosbag", the topic and the joint."""
        return {**super().origin, "format": "rosbag", "topic": self.topic, "joint": self.joint}

    def sliced(self, rows: slice, note: str) -> "BagTable":
        """The table cut to a contiguous range of samples, with a note saying how."""
        columns = {name: values[rows] for name, values in self.columns.items()}
        return dataclasses.replace(self, columns=columns, message_numbers=self.message_numbers[rows],
                                   notes=(*self.notes, note))

    def line_of(self, index: int) -> int:
        """The message's 1-based number in its topic."""
        return int(self.message_numbers[index]) + 1

    def column_label(self, name: str) -> str:
        """'velocity of joint 'j1'': the field a column came from."""
        field_name = {"q": "position", "qd": "velocity", "tau": "effort"}.get(name, name)
        return f"{field_name} of joint {self.joint!r}"

    def error(self, problem: str, index: int | None = None, name: str | None = None) -> LogError:
        """A LogError at the sample's message (number on the topic and time from the start)."""
        where = []
        if index is not None:
            where.append(f"message {self.line_of(index)} on {self.topic} (t = {self.columns['t'][index]:.6g} s)")
        if name not in (None, "t"):  # the time's place is the message itself
            where.append(self.column_label(name))
        return LogError(self.path, problem, place=", ".join(where) or None)

    @property
    def description(self) -> str:
        """What was read, for the line above the readouts."""
        return f"joint {self.joint!r} on {self.topic}, {self.count} messages"

    @property
    def brief(self) -> str:
        """What was read in a few words: "'j1', 1000 messages"."""
        return f"{self.joint!r}, {self.count} messages"


def read_bag_table(path, joint: str, topic: str | None = None, *, progress=None, cancel=None) -> BagTable:
    """One joint's t, q, qd (when filled in every message) and tau from a bag; LogError on any problem."""
    path = os.fspath(path)
    reader = open_bag(path)
    try:
        topic, connections = _choose_topic(path, reader, topic)
        collected = _JointColumns(joint, sum(c.msgcount for c in connections))
        scan = _Scan(path, reader, connections, collected, progress, cancel)
        messages = scan.run()
    finally:
        reader.close()
    mismatched = scan.mismatch_text(messages)
    if mismatched is not None:  # values that cannot be told to belong to a joint: refused, not guessed
        raise LogError(path, f"arrays of other lengths than their joint names in {mismatched}; a JointState gives "
                       "one value per name, or none (jointid bag-info lists the others)")
    return _table(path, topic, joint, collected, messages)


def _choose_topic(path: str, reader, topic: str | None):
    """(topic, connections) of the JointState topic to read; LogError naming the ones there."""
    topics = joint_state_topics(reader)
    if not topics:
        present = ", ".join(f"{c.topic} ({c.msgtype})" for c in reader.connections) or "none"
        raise LogError(path, f"has no sensor_msgs/JointState topic (topics: {present})")
    if topic is None:
        if len(topics) == 1:
            topic = next(iter(topics))
        elif DEFAULT_TOPIC in topics:
            topic = DEFAULT_TOPIC
        else:
            raise LogError(path, f"has several JointState topics ({', '.join(sorted(topics))}); choose one with --topic")
    if topic not in topics:
        raise LogError(path, f"has no JointState topic {topic}; JointState topics: {', '.join(sorted(topics))}")
    return topic, topics[topic]


def _table(path: str, topic: str, joint: str, found: _JointColumns, messages: int) -> BagTable:
    """Check what was collected and build the table: sorted times, fields filled, one line per problem."""
    where = f"on {topic}"
    if messages == 0:
        raise LogError(path, f"has no messages {where}")
    if found.count == 0:
        names = ", ".join(repr(n) for n in found.names_seen) or "none"
        raise LogError(path, f"no joint {joint!r} in any message {where}; joints there: {names}")
    if found.ambiguous is not None:
        raise LogError(path, f"message {found.ambiguous + 1} {where} names joint {joint!r} more than once; "
                       "cannot tell which values are its")
    n = found.count
    values, times, filled = found.values[:, :n], found.times[:, :n], found.filled[:, :n]
    notes = []
    for field_name, column in (("position", "q"), ("effort", "tau")):
        row = 0 if column == "q" else 2
        if not filled[row].any():
            raise LogError(path, f"joint {joint!r} has no {field_name} in any message {where} (the arrays are "
                           f"empty); jointid needs {'its angle' if column == 'q' else 'its torque'}")
        if not filled[row].all():
            first = int(times[2, np.flatnonzero(~filled[row])[0]])
            raise LogError(path, f"message {first + 1} {where} has no {field_name} for joint {joint!r}")
    velocity = bool(filled[1].all())
    if filled[1].any() and not velocity:
        notes.append(f"velocity of {joint!r} is filled in only {int(filled[1].sum())} of {n} messages, "
                     "so qd is estimated from position.")
    if n < messages:
        notes.append(f"joint {joint!r} is in {n} of the {messages} messages {where}; the others are skipped.")
    header, source = _times(times[0], times[1])
    if source == "receive time":
        notes.append("every header.stamp is zero, so time is the bag's receive time.")
    order = None
    steps = np.diff(header)
    if (steps < 0).any():
        order = np.argsort(header, kind="stable")
        notes.append(f"{int((steps < 0).sum())} messages arrived out of stamp order; sorted by {source}.")
        header = header[order]
    # A copy, so the collector's stamp and receive-time arrays are freed once the table is built.
    numbers = (times[2] if order is None else times[2][order]).astype(np.int32 if messages < 2**31 else np.int64)
    # Repeated stamps are left to the shared time checks: exact repeats dropped, others refused.
    t = (header - header[0]) * 1e-9
    columns = {"t": t, "q": values[0], **({"qd": values[1]} if velocity else {}), "tau": values[2]}
    if order is not None:
        columns = {name: (v if name == "t" else v[order]) for name, v in columns.items()}
    else:
        columns = {name: np.ascontiguousarray(v) for name, v in columns.items()}
    table = BagTable(
        path=path, columns=columns, positions={name: i + 1 for i, name in enumerate(columns)}, ignored=(),
        segments=(), notes=tuple(notes), topic=topic, joint=joint, message_numbers=numbers,
        read_as=tuple((name, {"t": source, "q": "position", "qd": "velocity", "tau": "effort"}[name])
                      for name in columns),
    )
    check_finite(table)
    return table
