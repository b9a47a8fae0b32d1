"""Read a joint from a WPILib data log (.wpilog), checked like a CSV log; recognise SysId routine logs.

The file is read with WPILib's own reader, robotpy-wpiutil's
`wpiutil.log.DataLogReader` (the optional extra `jointid[wpilib]`, imported
only here and only when a data log is opened). Its format (allwpilib's
`datalog.adoc`): a "WPILOG" header, then records, each with an entry id, a
time stamp in microseconds and a payload; entry 0 holds the control records
that start an entry (its name, type and metadata), finish it or change its
metadata.

Entries are sampled at their own times, so they are put on one time base: the
position entry's time stamps (the velocity's without one), because q is what the derivatives are estimated
from and interpolating it would smooth the very signal they come from; every
other entry is interpolated linearly at those times (a SysId loop logs its
voltage, position and velocity microseconds apart, so this is their own value),
and a sample where another entry has no record within three of its median steps
either side (a gap between tests) is left out.

SysId routine logs (what WPILib's SysIdRoutineLog writes): a string entry
`sysid-test-state-<routine>` recorded every loop with the test under way
("quasistatic-forward", "quasistatic-reverse", "dynamic-forward",
"dynamic-reverse", then "none"), and double entries `voltage-<motor>-<routine>`,
`position-<motor>-<routine>` and `velocity-<motor>-<routine>` whose metadata is
the unit's name (Java: "Volt", "Rotation", "Rotation per Second"; C++: "volt",
"turn", "turns_per_second"). Such a log is split into one run per test: a sample
belongs to the last state recorded up to STATE_LAG after it, because
SysIdRoutine records the state just after the motor's values in each loop,
and a test run twice is two runs (split where another state was recorded
between two samples, or at a time gap). Teams' logs also hold lengths
("Meter": read in metres, never as an angle), routines with a velocity and
no position (q is the velocity integrated), and several motors of one
routine (read together, pooled as one mechanism). Times are the log's own
time stamps in seconds, as log-info lists them and windows take them.
Other logs (AdvantageKit, CTRE) name their entries with an EntryMap
(`--entry q=/Arm/Position,tau=/Arm/Voltage`, and `state=` for a test-state
entry), and their unit with `--units` when the metadata does not say.

A file cut short: the reader stops quietly at an incomplete record, so the last
record it gives is checked to end where the file ends (`_ends_the_file`). A
damaged one: the reader decodes texts and numbers only when asked, and fails with
a UnicodeDecodeError or TypeError on bytes that are not UTF-8 or a record of the
wrong size; such a failure is turned into one LogError naming the entry and what
is wrong with it (`_damaged`).
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import re
import shlex
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..files import FileRefused, check_readable, open_for_reading, shown_command
from ..text_safety import shown_name
from .pipeline import check_finite
from .table import LoadCancelled, LogError, LogTable
from .velocity_lag import lag_note, velocity_lag

EXTRA_HINT = "reading WPILib data logs needs the optional robotpy-wpiutil package: pip install 'jointid[wpilib]'"
"""The one line shown when robotpy-wpiutil is not installed."""

SUFFIX = ".wpilog"
"""The ending WPILib gives its data logs."""

MAGIC = b"WPILOG"
"""The first bytes of every data log."""

HEADER_BYTES = 12
""""WPILOG", a 2-byte version and a 4-byte length of the extra header that follows."""

NUMERIC_TYPES = {"double": "getDouble", "float": "getFloat", "int64": "getInteger"}
"""Entry types read as numbers, and the record method that decodes each."""

NUMBER_BYTES = {"double": 8, "float": 4, "int64": 8}
"""The payload size of one record of each numeric type (the format's specification)."""

START_TEXTS = ("name", "type", "metadata")
"""The length-prefixed strings of a Start control record's payload, after its type byte and 4-byte entry id."""

STATE_PREFIX = "sysid-test-state-"
"""The start of a SysId routine's test-state entry's name; the routine's name follows."""

MOTOR_KINDS = ("voltage", "position", "velocity")
"""The SysId motor entries, named `<kind>-<motor>-<routine>`."""

TESTS = ("quasistatic-forward", "quasistatic-reverse", "dynamic-forward", "dynamic-reverse")
"""The test states that make a run; "none" (and any other text) between them makes none."""

STATE_LAG = 1e-3
"""Seconds a state record may follow a sample and still be that sample's (the same loop iteration)."""

GAP_STEPS = 3.0
"""A sample is left out where another entry's neighbouring records are more than this many of its median steps
apart."""

NEAR_STEPS = 0.1
"""A sample is kept beside a gap when another entry has a record this many of its median steps from it, whose
value interpolation then all but gives (a SysId loop's records are microseconds apart)."""

RUN_GAP_STEPS = 25.0
"""A time gap of this many median steps between two samples of one test ends a run (0.5 s at 50 Hz): a test
run again after a pause is a second run, never one run across the gap."""

MIN_RUN_SAMPLES = 20
"""A test shorter than this (in position samples) is not made a run; a note names it."""

UNITS = {"rotations": 2 * math.pi, "radians": 1.0, "degrees": math.pi / 180}
"""Angle units --units takes, and radians per unit."""

LINEAR_UNIT = "meters"
"""The unit a length is read in (--units meters): a linear coordinate, never converted to an angle."""

UNIT_CHOICES = (*UNITS, LINEAR_UNIT)
"""Every unit --units takes."""

_UNIT_WORDS = {
    "rotations": ("rotation", "turn", "revolution", "rot", "rev", "tr", "r"),
    "radians": ("radian", "rad"),
    "degrees": ("degree", "deg", "°"),
}
_LENGTHS = {"meter": 1.0, "metre": 1.0, "m": 1.0, "centimeter": 0.01, "centimetre": 0.01, "cm": 0.01,
            "millimeter": 0.001, "millimetre": 0.001, "mm": 0.001, "inch": 0.0254, "in": 0.0254, "foot": 0.3048,
            "feet": 0.3048, "ft": 0.3048}
"""Length units a metadata may name, and metres per unit."""
_PER_SECOND = re.compile(r"(\s*(/|_?per_?|\s+per\s+)\s*(s|sec|second)s?)$")

RECORD_BYTES_GUESS = 16
"""Bytes of a typical record (a double with a 4-byte time stamp), for the progress bar only."""

PROGRESS_RECORDS = 1 << 16
"""Records read between progress reports and cancel checks."""

ProgressCallback = Callable[[int, int], None]
CancelCheck = Callable[[], bool]


def looks_like_wpilog(path) -> bool:
    """True for a file ending in .wpilog or starting with "WPILOG" (read only when it is a regular file)."""
    path = os.fspath(path)
    if path.lower().endswith(SUFFIX):
        return True
    try:
        with open_for_reading(path) as handle:
            return handle.read(len(MAGIC)) == MAGIC
    except FileRefused:
        return False


# ---------------------------------------------------------------------------------------------- units


def unit_text(metadata: str) -> str | None:
    """The unit a metadata string names: the string itself, or a JSON object's "unit"/"units"; None if empty."""
    text = (metadata or "").strip()
    if text.startswith("{"):
        try:
            found = json.loads(text)
        except (ValueError, RecursionError):  # nested too deep for the parser: no unit it can read either
            return None
        value = found.get("unit", found.get("units")) if isinstance(found, dict) else None
        return str(value).strip() or None if value is not None else None
    return text or None


def angle_unit(text: str | None, rate: bool = False) -> tuple[str | None, float]:
    """(unit, per second factor) of a unit's name: ('rotations', 1.0) for 'Rotation' or 'Rotation per Second',
    ('rotations', 1/60) for 'rpm'; (None, 1.0) when the name is no angle unit it knows."""
    if text is None:
        return None, 1.0
    word = text.strip().lower()
    if rate and word in ("rpm", "rotations per minute", "rotation per minute"):
        return "rotations", 1 / 60
    if rate and word == "rps":
        return "rotations", 1.0
    if rate:
        word = _PER_SECOND.sub("", word).strip()
    for unit, words in _UNIT_WORDS.items():
        if word in words or (word.endswith("s") and word[:-1] in words):
            return unit, 1.0
    return None, 1.0


def metres_per(text: str | None) -> float | None:
    """Metres per unit of a length's (or a length per second's) name: 1.0 for 'Meter' or 'Meter per Second', 0.0254
    for 'inches'; None when the name is no length."""
    if text is None:
        return None
    word = _PER_SECOND.sub("", text.strip().lower()).strip()
    if word in _LENGTHS:
        return _LENGTHS[word]
    if word.endswith("s") and word[:-1] in _LENGTHS:
        return _LENGTHS[word[:-1]]
    return None


def is_linear(text: str | None) -> bool:
    """True when a unit's name is a length: a drive's or an elevator's position, read in metres."""
    return metres_per(text) is not None


# ---------------------------------------------------------------------------------------------- opening


def _reader_class():
    """wpiutil.log.DataLogReader, imported now; None when robotpy-wpiutil is not installed."""
    try:
        from wpiutil.log import DataLogReader
    except ImportError:
        return None
    return DataLogReader


def open_reader(path):
    """An opened DataLogReader; LogError (one line) when the file cannot be read as a data log."""
    path = os.fspath(path)
    if not path.strip():
        raise LogError("(no file)", "cannot open: the path is empty; give a WPILib data log's path")
    reader_class = _reader_class()
    if reader_class is None:
        raise LogError(path, EXTRA_HINT)
    try:
        check_readable(path)
    except FileRefused as error:
        raise LogError(path, error.problem) from None
    try:
        reader = reader_class(path)
    except (OSError, RuntimeError, ValueError) as error:
        raise LogError(path, f"cannot open: {error}") from None
    if not reader.isValid():
        raise LogError(path, "is not a WPILib data log (it does not start with a WPILOG header of version 1.0)")
    return reader


def extra_header(path: str, reader) -> str:
    """The log's extra header string; LogError when its bytes are not UTF-8."""
    try:
        return reader.getExtraHeader()
    except UnicodeDecodeError as error:
        raise LogError(path, f"is damaged: its extra header holds bytes that are not UTF-8 ({_bad_byte(error)})"
                       ) from None


def _bad_byte(error: UnicodeDecodeError) -> str:
    """Which byte a UnicodeDecodeError stopped at, e.g. 'byte 0xff at 3'."""
    return f"byte 0x{error.object[error.start]:02x} at {error.start}"


def _ends_the_file(path: str, size: int, record, extra_header: str) -> bool:
    """True when the last record read (or the header, when there is none) ends exactly where the file does."""
    if record is None:
        return size == HEADER_BYTES + len(extra_header.encode())
    payload = bytes(record.getRaw())
    with open_for_reading(path) as handle:
        handle.seek(max(0, size - len(payload) - 17))
        tail = handle.read()
    if not tail.endswith(payload):
        return False
    # The reader gives C++'s signed integers; the file holds unsigned ones (an id of 2**31 reads as -2**31).
    wanted = (record.getEntry() & 0xFFFF_FFFF, record.getSize() & 0xFFFF_FFFF, record.getTimestamp() & (2**64 - 1))
    end = len(tail) - len(payload)
    for length in range(3, 18):  # 1 header byte, an id of 1-4 bytes, a size of 1-4, a time stamp of 1-8
        start = end - length
        if start < 0:
            break
        lengths = tail[start]
        id_bytes, size_bytes, time_bytes = (lengths & 3) + 1, ((lengths >> 2) & 3) + 1, ((lengths >> 4) & 7) + 1
        if 1 + id_bytes + size_bytes + time_bytes != length:
            continue
        p = start + 1
        fields = []
        for width in (id_bytes, size_bytes, time_bytes):
            fields.append(int.from_bytes(tail[p: p + width], "little"))
            p += width
        if tuple(fields) == wanted:
            return True
    return False


# ---------------------------------------------------------------------------------------------- reading


@dataclass
class Entry:
    """One entry of a data log: its name, type, metadata, and how many records it has and when."""

    id: int
    name: str
    type: str
    metadata: str
    records: int = 0
    first_us: int | None = None
    last_us: int | None = None

    @property
    def unit(self) -> str | None:
        """The unit its metadata names, or None."""
        return unit_text(self.metadata)

    @property
    def numeric(self) -> bool:
        """True for a number per record (double, float or int64)."""
        return self.type in NUMERIC_TYPES

    @property
    def rate(self) -> float | None:
        """Mean records per second between its first and last record; None with fewer than two."""
        if self.records < 2 or self.first_us is None or self.last_us == self.first_us:
            return None
        return (self.records - 1) / ((self.last_us - self.first_us) * 1e-6)

    def to_dict(self) -> dict:
        """JSON-ready values."""
        return {"name": self.name, "type": self.type, "metadata": self.metadata, "unit": self.unit,
                "records": self.records, "rate_hz": self.rate,
                "first_s": None if self.first_us is None else self.first_us * 1e-6,
                "last_s": None if self.last_us is None else self.last_us * 1e-6}


@dataclass(frozen=True, eq=False)
class Series:
    """The records of one entry: time stamps (us) and values (numbers, or texts for a string entry)."""

    entry: Entry
    times: np.ndarray
    """(n,) int64 microseconds."""
    values: np.ndarray
    """(n,) float64, or an object array of str."""


def read_entries(path, wanted: Callable[[str, str], bool], *, count_all: bool = False,
                 progress: ProgressCallback | None = None, cancel: CancelCheck | None = None
                 ) -> tuple[dict[str, Entry], dict[str, Series]]:
    """Every entry's start data (and, with `count_all`, its record count and first and last time), and the
    records of the entries `wanted(name, type)` picks; LogError for a file that is not a whole data log.

    An entry finished and started again under the same name continues its series.
    """
    path = os.fspath(path)
    reader = open_reader(path)
    size = os.path.getsize(path)
    entries: dict[str, Entry] = {}
    by_id: dict[int, Entry] = {}
    collected: dict[str, tuple[list, list]] = {}
    sinks: dict[int, tuple] = {}
    header = extra_header(path, reader)
    record = None
    try:
        for index, record in enumerate(reader):
            entry = record.getEntry()
            if entry == 0:
                _control(path, record, entries, by_id, sinks, collected, wanted)
            else:
                sink = sinks.get(entry)
                if sink is not None:
                    times, values, decode = sink
                    times.append(record.getTimestamp())
                    values.append(decode(record))
                if count_all:
                    _count(by_id.get(entry), record)
            if not index & (PROGRESS_RECORDS - 1) and index:
                if cancel is not None and cancel():
                    raise LoadCancelled(path)
                if progress is not None:
                    progress(min(index * RECORD_BYTES_GUESS, size - 1), size)
    except (UnicodeDecodeError, TypeError) as error:  # caught here, not per record: the loop is the hot path
        raise _damaged(path, record, by_id, error) from None
    if not _ends_the_file(path, size, record, header):
        raise LogError(path, "is cut short or damaged: its last record ends before the file does (a log copied "
                       "while the robot was still writing it?)")
    if progress is not None:
        progress(size, size)
    series = {}
    for name, (times, values) in collected.items():
        entry = entries[name]
        array = np.asarray(values, dtype=float) if entry.numeric else np.asarray(values, dtype=object)
        series[name] = Series(entry, np.asarray(times, dtype=np.int64), array)
    return entries, series


def _control(path: str, record, entries, by_id, sinks, collected, wanted) -> None:
    """Apply a control record: an entry started (collected when wanted), finished, or given new metadata."""
    if record.isStart():
        data = record.getStartData()
        _check_metadata(path, data.name, data.metadata)
        entry = entries.get(data.name)
        if entry is None:
            entry = entries[data.name] = Entry(data.entry, data.name, data.type, data.metadata)
        by_id[data.entry] = entry
        sinks.pop(data.entry, None)  # a Start (re)assigns the id: what its records were decoded as before is gone
        decode = NUMERIC_TYPES.get(data.type, "getString" if data.type == "string" else None)
        if decode is not None and data.type == entry.type and wanted(data.name, data.type):
            times, values = collected.setdefault(data.name, ([], []))
            sinks[data.entry] = (times, values, getattr(type(record), decode))
    elif record.isFinish():
        finished = record.getFinishEntry()
        by_id.pop(finished, None)
        sinks.pop(finished, None)
    elif record.isSetMetadata():
        data = record.getSetMetadataData()
        entry = by_id.get(data.entry)
        if entry is not None:
            _check_metadata(path, entry.name, data.metadata)
            entry.metadata = data.metadata


def _check_metadata(path: str, name: str, metadata: str) -> None:
    """LogError when an entry's metadata is JSON nested too deep to parse (no logger writes that; a hostile file)."""
    if metadata.lstrip().startswith(("{", "[")):
        try:
            json.loads(metadata)
        except RecursionError:
            raise LogError(path, f"is damaged: the metadata of entry {name!r} is JSON nested too deep to read "
                           f"({len(metadata)} characters)") from None
        except ValueError:
            pass  # not JSON: a unit's name that happens to start with a brace, read as text


def _damaged(path: str, record, by_id: dict, error: Exception) -> LogError:
    """The one-line LogError for a record the reader failed to decode: texts that are not UTF-8, or a number's
    record of the wrong size; raises `error` again when it is neither (a fault of this program, not the file's)."""
    stamp = f"{(record.getTimestamp() & (2**64 - 1)) * 1e-6:.6f} s"
    raw = bytes(record.getRaw())
    if record.getEntry() == 0:
        kind, fields = ("Start", START_TEXTS) if record.isStart() else ("SetMetadata", ("metadata",))
        entry_id = int.from_bytes(raw[1:5], "little")
        if isinstance(error, UnicodeDecodeError):
            field = _bad_text(raw[5:], fields)
            return LogError(path, f"is damaged: the {field} in the {kind} record of entry id {entry_id} (time stamp "
                            f"{stamp}) is not UTF-8 ({_bad_byte(error)} of it)")
        raise error
    entry = by_id.get(record.getEntry())
    if entry is None:
        raise error
    if isinstance(error, UnicodeDecodeError):
        return LogError(path, f"is damaged: entry {entry.name!r} has a string record at {stamp} that is not UTF-8 "
                        f"({_bad_byte(error)})")
    expected = NUMBER_BYTES.get(entry.type)
    if expected is None or len(raw) == expected:
        raise error
    return LogError(path, f"is damaged: entry {entry.name!r} is of type {entry.type} ({expected} bytes a record) "
                    f"but its record at {stamp} holds {len(raw)} bytes")


def _bad_text(payload: bytes, fields: tuple[str, ...]) -> str:
    """The first of a control record's length-prefixed strings `fields` whose bytes are not UTF-8."""
    at = 0
    for field in fields:
        length = int.from_bytes(payload[at: at + 4], "little")
        text = payload[at + 4: at + 4 + length]
        at += 4 + length
        try:
            text.decode("utf-8")
        except UnicodeDecodeError:
            return field
    return "text"


def _count(entry: Entry | None, record) -> None:
    """Count one data record of an entry (log-info's survey)."""
    if entry is None:
        return
    stamp = record.getTimestamp()
    entry.records += 1
    if entry.first_us is None:
        entry.first_us = stamp
    entry.last_us = stamp


# ---------------------------------------------------------------------------------------------- SysId


@dataclass(frozen=True)
class SysIdRoutine:
    """The entries of one motor of a SysId routine log (a position, a velocity, or both)."""

    routine: str
    motor: str
    state: str
    voltage: str
    position: str | None
    velocity: str | None

    @property
    def entry_map(self):
        """The same entries as a conventions.EntryMap."""
        from .conventions import EntryMap

        pairs = [*([("q", self.position)] if self.position else []), *([("qd", self.velocity)] if self.velocity
                                                                         else []),
                 ("tau", self.voltage), ("state", self.state)]
        return EntryMap(tuple(pairs), "SysId")


def sysid_routines(entries: dict[str, Entry]) -> tuple[list[SysIdRoutine], list[str]]:
    """(each routine and motor with a voltage entry and a position or velocity entry, routines that have a
    test-state entry but no voltage entry)."""
    found, lacking = [], []
    for state in sorted(name for name, entry in entries.items()
                        if name.startswith(STATE_PREFIX) and entry.type == "string"):
        routine = state[len(STATE_PREFIX):]
        motors = _motor_entries(entries, routine)
        complete = [(motor, kinds) for motor, kinds in sorted(motors.items())
                    if "voltage" in kinds and ("position" in kinds or "velocity" in kinds)]
        if not any("voltage" in kinds for kinds in motors.values()):
            lacking.append(routine)
        found += [SysIdRoutine(routine, motor, state, kinds["voltage"], kinds.get("position"), kinds.get("velocity"))
                  for motor, kinds in complete]
    return found, lacking


def _motor_entries(entries: dict[str, Entry], routine: str) -> dict[str, dict[str, str]]:
    """Motor -> {kind: entry name} of the numeric `<kind>-<motor>-<routine>` entries of one routine."""
    motors: dict[str, dict[str, str]] = {}
    for name, entry in entries.items():
        if not entry.numeric or not name.endswith("-" + routine):
            continue
        for kind in MOTOR_KINDS:
            if name.startswith(kind + "-") and len(name) > len(kind) + len(routine) + 2:
                motors.setdefault(name[len(kind) + 1: -len(routine) - 1], {})[kind] = name
    return motors


def _is_sysid_name(name: str, entry_type: str) -> bool:
    """Whether an entry may belong to a SysId routine log (read while the names are not known yet)."""
    return name.startswith(STATE_PREFIX) or (entry_type in NUMERIC_TYPES and name.startswith(
        tuple(kind + "-" for kind in MOTOR_KINDS)))


def test_runs(times: np.ndarray, states: np.ndarray, samples: np.ndarray) -> list[tuple[str, slice]]:
    """(test, rows) of each stretch of samples (time stamps in us, sorted) under one of the TESTS, in time order:
    each sample takes the last state recorded up to STATE_LAG after it. A stretch ends where the state changes,
    where a state record of another test (or "none") falls between two samples though no sample took it (a
    routine logs only while a test runs), and at a time gap of RUN_GAP_STEPS loop periods: a test run twice is
    two runs."""
    if not len(times) or not len(samples):
        return []
    lag = int(STATE_LAG * 1e6)
    order = np.argsort(times, kind="stable")
    times, states = times[order], states[order]
    index = np.searchsorted(times, samples + lag, side="right") - 1
    labels = np.where(index >= 0, states[np.maximum(index, 0)], "none")
    # changes[i]: how many times the state changed up to record i, so two samples with the same count saw one
    # unbroken stretch of records.
    changes = np.concatenate(([0], np.cumsum(states[1:] != states[:-1])))
    seen = np.where(index >= 0, changes[np.maximum(index, 0)], -1)
    steps = np.diff(samples)
    positive = steps[steps > 0]
    gap = RUN_GAP_STEPS * float(np.median(positive)) if len(positive) else math.inf
    breaks = np.concatenate(([False], (seen[1:] != seen[:-1]) | (steps > gap)))
    runs, start = [], 0
    for k in range(1, len(labels) + 1):
        if k == len(labels) or labels[k] != labels[start] or breaks[k]:
            if labels[start] in TESTS:
                runs.append((str(labels[start]), slice(start, k)))
            start = k
    return runs


def run_names(runs: list[tuple[str, slice]]) -> list[tuple[str, slice]]:
    """The runs named by their test, "#1", "#2"... after the test's name when it was run more than once."""
    counts: dict[str, int] = {}
    for test, _ in runs:
        counts[test] = counts.get(test, 0) + 1
    seen: dict[str, int] = {}
    named = []
    for test, rows in runs:
        seen[test] = seen.get(test, 0) + 1
        named.append((test if counts[test] == 1 else f"{test} #{seen[test]}", rows))
    return named


# ---------------------------------------------------------------------------------------------- one joint


@dataclass(frozen=True, eq=False)
class WpilogTable(LogTable):
    """One joint's samples from a data log, as a LogTable; messages name the entry and the time."""

    entries: tuple[tuple[str, str], ...] = ()
    """(quantity, entry name) of each entry read."""
    stamps: np.ndarray | None = None
    """(N,) int64 microseconds of each sample (the position entry's record, or the velocity's without one)."""
    units: tuple[tuple[str, str], ...] = ()
    """(quantity, unit the log gave it in) of q and qd: 'rotations', 'radians' or 'degrees' for an angle (the
    column converted to radians), or 'meters' for a length (kept as a linear coordinate, in metres)."""
    run: str | None = None
    """The SysId test run this table is ("quasistatic-forward", "quasistatic-forward #2"), or None for the whole
    log."""
    runs: tuple[tuple[str, slice], ...] = ()
    """(test run's name, rows) of each SysId test run in the table, when a test-state entry was read."""
    routine: SysIdRoutine | None = None
    """The SysId routine and motor read, when the log is one."""
    position_source: str = "logged"
    """Where q comes from: "logged" (a position entry) or "integrated velocity" (a routine that logged no
    position: q is its velocity integrated, no absolute angle, so no model may take cos of it)."""
    velocity_lag_s: float | None = None
    """How far the logged velocity lags the position's derivative (s, cross-correlation over the routine); None
    where it cannot be checked (no velocity or no position logged)."""
    left_out: tuple[tuple[str, str], ...] = ()
    """(test run, why) of each test run of the routine that is not a run of the fit."""
    motors: tuple[str, ...] = ()
    """The motors of the routine read together, when several are pooled (each run is then named by its motor)."""
    sysid_notes: tuple[str, ...] = ()
    """What reading the routine decided (motors, units, repeated tests, the velocity's lag, tests left out), for
    the text of a SysId fit."""

    @property
    def linear(self) -> bool:
        """True when q is a length in metres (a drive, an elevator), not an angle."""
        return dict(self.units).get("q", dict(self.units).get("qd")) == LINEAR_UNIT

    @property
    def origin(self) -> dict:
        """LogTable.origin with format "wpilog", the entries, units, SysId test, where q came from and the logged
        velocity's lag."""
        return {**super().origin, "format": "wpilog", "entries": dict(self.entries), "units": dict(self.units),
                "sysid_test": self.run, "sysid_motor": None if self.routine is None else self.routine.motor,
                "position_source": self.position_source, "velocity_lag_s": self.velocity_lag_s,
                "time_base": "the data log's own time stamps (s)",
                "sysid_left_out": [{"run": name, "why": why} for name, why in self.left_out]}

    def sliced(self, rows: slice, note: str) -> WpilogTable:
        """The table cut to a contiguous range of samples, with a note saying how."""
        columns = {name: values[rows] for name, values in self.columns.items()}
        runs = tuple((test, slice(max(r.start - rows.start, 0), min(r.stop, rows.stop) - rows.start))
                     for test, r in self.runs if r.stop > rows.start and r.start < rows.stop)
        return dataclasses.replace(self, columns=columns, stamps=self.stamps[rows], runs=runs,
                                   notes=(*self.notes, note))

    def line_of(self, index: int) -> int:
        """The sample's 1-based number in the position entry."""
        return index + self.first + 1

    def column_label(self, name: str) -> str:
        """The entry a column came from: "entry 'position-arm-arm'"."""
        return f"entry {dict(self.entries).get(name, name)!r}"

    def error(self, problem: str, index: int | None = None, name: str | None = None) -> LogError:
        """A LogError at the sample's time stamp and entry."""
        where = []
        if index is not None:
            where.append(f"t = {self.stamps[index] * 1e-6:.6f} s")
        if name not in (None, "t"):
            where.append(self.column_label(name))
        return LogError(self.path, problem, place=", ".join(where) or None)

    @property
    def description(self) -> str:
        """What was read, for the line above the readouts."""
        what = f"{self.run} of SysId routine {self.routine.routine!r}" if self.run and self.routine else \
            (self.run or "entries " + ", ".join(name for key, name in self.entries if key != "state"))
        return f"{what}, {self.count} samples"

    @property
    def brief(self) -> str:
        """What was read in a few words."""
        return f"{self.run or dict(self.entries).get('q', dict(self.entries).get('qd', ''))}, {self.count} samples"

    def run_tables(self) -> list[WpilogTable]:
        """One table per SysId test run, named by it (and by its motor when several motors are pooled)."""
        tables = []
        for name, rows in self.runs:
            if len(self.motors) > 1 and self.routine is not None:
                name = f"{self.routine.motor} {name}"
            start = self.stamps[rows.start] * 1e-6
            end = self.stamps[rows.stop - 1] * 1e-6
            cut = self.sliced(rows, f"SysId test {name}: {rows.stop - rows.start} samples, t = {start:.6g} to "
                              f"{end:.6g} s of the log.")
            # Exclusions and windows count in the log's own seconds, as its times do.
            tables.append(dataclasses.replace(cut, run=name, runs=(), time_origin=0.0))
        return tables


def read_wpilog_table(path, entry_map=None, units: str | None = None, *, motor: str | None = None,
                      repeats: str = "all", progress=None, cancel=None) -> WpilogTable:
    """One joint's table from a data log (read_wpilog_tables' only one); LogError when a SysId routine has several
    motors and `motor` names none of them."""
    tables = read_wpilog_tables(path, entry_map, units, motor=motor, repeats=repeats, progress=progress,
                                cancel=cancel)
    if len(tables) > 1:
        choices = ", ".join(repr(table.routine.motor) for table in tables)
        raise LogError(os.fspath(path), f"SysId routine {tables[0].routine.routine!r} has {len(tables)} motors "
                       f"({choices}); read one at a time (`{fit_line(path, '--sysid-motor', tables[0].routine.motor)}`)"
                       " or all pooled with load_joint_logs")
    return tables[0]


def read_wpilog_tables(path, entry_map=None, units: str | None = None, *, motor: str | None = None,
                       repeats: str = "all", progress=None, cancel=None) -> list[WpilogTable]:
    """The joint's table from a data log, one per motor of a SysId routine: t (s, the log's own time stamps), q
    and qd (radians, or metres for a length), qdd and tau (as logged); the entries of `entry_map` (a
    conventions.EntryMap), or a SysId routine's; LogError on any problem.

    `units` ('rotations', 'radians', 'degrees' or 'meters') is the unit of q, qd and qdd, over their metadata's.
    `motor` names one motor of the routine (or the routine: all its motors); by default every motor of the log's
    one routine is read, pooled as runs of one mechanism. `repeats` is 'all' (every run of a test repeated) or
    'first' (each test's first run, as SysId's analysis takes).
    """
    path = os.fspath(path)
    if units is not None and units not in UNIT_CHOICES:
        raise LogError(path, f"unknown unit {units!r}; --units takes {', '.join(UNIT_CHOICES)}")
    if repeats not in REPEATS:
        raise LogError(path, f"unknown choice {repeats!r} for a repeated test; one of {', '.join(REPEATS)}")
    if entry_map is not None:
        names = {name for _, name in entry_map.pairs}
        wanted = lambda name, kind: name in names  # noqa: E731
    else:
        wanted = _is_sysid_name
    entries, series = read_entries(path, wanted, progress=progress, cancel=cancel)
    if entry_map is not None:
        if motor is not None:
            raise LogError(path, "--sysid-motor: only for a SysId routine's entries, not with --entry")
        return [_joint_table(path, entries, series, _checked_pairs(path, entries, entry_map), units, None,
                             entry_map.flag, repeats)]
    routines = _choose_routines(path, entries, motor)
    tables = [_joint_table(path, entries, series, dict(routine.entry_map.pairs), units, routine, "SysId", repeats)
              for routine in routines]
    if len(tables) > 1:
        motors = tuple(routine.motor for routine in routines)
        notes = _pooled_notes(path, tables, motors)
        tables = [dataclasses.replace(table, motors=motors, sysid_notes=notes) for table in tables]
    return tables


def _pooled_notes(path: str, tables: list[WpilogTable], motors: tuple[str, ...]) -> tuple[str, ...]:
    """The reading notes of several motors pooled, each said once for all of them."""
    notes = [f"SysId routine {tables[0].routine.routine!r} drives {len(motors)} motors "
             f"({', '.join(map(repr, motors))}): pooled as one mechanism, each motor's tests its runs; one motor's "
             f"own fit: `{fit_line(path, '--sysid-motor', motors[0])}` (or another motor's name)."]
    if tables[0].linear:
        notes.append("Their positions are lengths: q in metres, qd in m/s, a linear coordinate (the wheel or drum "
                     "turns; the gains are per metre), never an angle.")
    notes += [note for note in tables[0].sysid_notes if " was run " in note]
    integrated = [t.routine.motor for t in tables if t.position_source != "logged"]
    if integrated:
        notes.append(f"No position entry for {', '.join(map(repr, integrated))}: q is the logged velocity "
                     "integrated (trapezoids), no absolute angle; the velocity's lag cannot be checked there.")
    lags = [(t.routine.motor, t.velocity_lag_s) for t in tables if t.velocity_lag_s is not None]
    if lags:
        notes.append("The logged velocities lag the positions' derivatives by " + ", ".join(
            f"{lag * 1e3:.0f} ms ({motor})" for motor, lag in lags) + " (cross-correlation over the tests): the "
            "fit takes its speed from the positions. SysId's analysis takes the logged velocity, so its kA differs "
            "where this lag is large (a SPARK MAX averages position changes over 32 ms, eight deep).")
    left = [f"{t.routine.motor} {name}, {why}" for t in tables for name, why in t.left_out]
    if left:
        notes.append("Left out: " + "; ".join(left) + ".")
    return tuple(notes)


REPEATS = ("all", "first")
"""What a test run more than once gives: every run (the default), or the first (as SysId's analysis does)."""


def fit_line(path: str, *flags: str) -> str:
    """`jointid fit --wpilog PATH FLAGS...` quoted so that it pastes into a shell as is (a name with a character
    that is not printable escaped, as every name is shown)."""
    return shown_command(["jointid", "fit", "--wpilog", os.fspath(path), *flags])


def _checked_pairs(path: str, entries: dict[str, Entry], entry_map) -> dict[str, str]:
    """The entry map's quantity -> entry name, each entry present and of the right type; LogError otherwise."""
    for quantity, name in entry_map.pairs:
        if name not in entries:
            shown = ", ".join(sorted(entries)[:20]) + (", …" if len(entries) > 20 else "")
            raise LogError(path, f"{entry_map.flag} {quantity}={name}: the log has no entry {name!r}; its entries "
                           f"are {shown or 'none'} (jointid log-info lists them)")
        entry = entries[name]
        needed = "text (a string entry)" if quantity == "state" else "numbers (double, float or int64)"
        if (quantity == "state") != (entry.type == "string") or (quantity != "state" and not entry.numeric):
            raise LogError(path, f"{entry_map.flag} {quantity}={name}: entry {name!r} holds {entry.type}, not "
                           f"{needed}")
    pairs = dict(entry_map.pairs)
    if "q" not in pairs and "qd" not in pairs:
        raise LogError(path, f"{entry_map.flag} names no entry for q or qd; jointid needs the joint's position "
                       "(q=ENTRY) or its velocity (qd=ENTRY)")
    if "tau" not in pairs:
        raise LogError(path, f"{entry_map.flag} names no entry for tau; jointid needs its effort (tau=ENTRY, a "
                       "voltage or torque)")
    return pairs


def _choose_routines(path: str, entries: dict[str, Entry], motor: str | None) -> list[SysIdRoutine]:
    """The motors of the log's SysId routine to read: all of its one routine, or those `motor` names; LogError
    saying what is missing when there is none."""
    found, lacking = sysid_routines(entries)
    if motor is not None:
        chosen = [r for r in found if motor in (r.motor, r.routine)]
        if not chosen:
            listed = ", ".join(sorted({repr(r.motor) for r in found} | {repr(r.routine) for r in found}))
            raise LogError(path, f"--sysid-motor {motor!r}: the log has no SysId motor or routine of that name; "
                           f"its are {listed or 'none'} (jointid log-info lists them)")
        return chosen
    if not found:
        states = sorted(name for name, entry in entries.items()
                        if name.startswith(STATE_PREFIX) and entry.type == "string")
        if states:
            routine = states[0][len(STATE_PREFIX):]
            raise LogError(path, _missing_motor_entries(entries, routine))
        if not any(entry.numeric for entry in entries.values()):
            raise LogError(path, f"has no numeric entries (double, float or int64) among its {len(entries)} "
                           "entries: nothing to fit")
        raise LogError(path, "is no SysId routine log (no sysid-test-state-<routine> entry with voltage- and "
                       "position- or velocity-<motor>-<routine> entries); name its entries with --entry "
                       "q=ENTRY,tau=ENTRY (jointid log-info lists them)")
    routines = sorted({r.routine for r in found})
    if len(routines) > 1:
        listed = "; ".join(f"`{fit_line(path, '--sysid-motor', name)}`" for name in routines)
        raise LogError(path, f"has {len(routines)} SysId routines ({', '.join(map(repr, routines))}); fit one: "
                       f"{listed}")
    return found


def _missing_motor_entries(entries: dict[str, Entry], routine: str) -> str:
    """What a routine with a test-state entry lacks, in one sentence that starts with it."""
    motors = _motor_entries(entries, routine)
    logged = sorted(name for kinds in motors.values() for name in kinds.values())
    state = f"{STATE_PREFIX}{routine}"
    if not motors:
        return (f"no voltage entry for routine {routine!r}, nor any position- or velocity-<motor>-{routine}: its "
                f"test-state entry {state!r} has no numeric entry beside it (the routine's log callback wrote only "
                "the state): without the voltage there is no effort to fit; name the joint's entries with --entry "
                f"{shlex.quote('q=ENTRY,tau=ENTRY,state=' + state)} (jointid log-info lists them)")
    if not any("voltage" in kinds for kinds in motors.values()):
        return (f"no voltage entry for routine {routine!r} (voltage-<motor>-{routine}; it logged "
                f"{', '.join(logged)}): without the voltage there is no effort to fit (name one with --entry)")
    return (f"no position or velocity entry for routine {routine!r} (it logged {', '.join(logged)}): beside a "
            f"voltage-<motor>-{routine} a fit needs position-<motor>-{routine} or velocity-<motor>-{routine}")


def _joint_table(path: str, entries: dict[str, Entry], series: dict[str, Series], pairs: dict[str, str],
                 units: str | None, routine: SysIdRoutine | None, flag: str, repeats: str = "all") -> WpilogTable:
    """Put the chosen entries on the position entry's time base (the velocity's without a position), convert
    angles to radians (a length stays in metres), split the test runs, check the logged velocity's lag."""
    base = "q" if "q" in pairs else "qd"
    position = series.get(pairs[base])
    if position is None or len(position.times) < 2:
        raise LogError(path, f"entry {pairs[base]!r} has {0 if position is None else len(position.times)} records; "
                       "a fit needs many")
    order = np.argsort(position.times, kind="stable")
    stamps = position.times[order]
    keep = np.ones(len(stamps), dtype=bool)
    columns_raw = {base: position.values[order]}
    notes, sysid_notes = [], []
    for quantity in ("qd", "qdd", "tau"):
        if quantity not in pairs or quantity == base:
            continue
        other = series.get(pairs[quantity])
        if other is None or len(other.times) < 2:
            raise LogError(path, f"entry {pairs[quantity]!r} has {0 if other is None else len(other.times)} "
                           "records; a fit needs many")
        values, inside = _interpolated(other, stamps)
        keep &= inside
        columns_raw[quantity] = values
    if not keep.all():
        notes.append(f"{int((~keep).sum())} of {len(keep)} samples of {pairs[base]!r} are left out: another entry "
                     "has no record near them (before its first, after its last, or in a gap).")
    stamps = stamps[keep]
    columns_raw = {name: values[keep] for name, values in columns_raw.items()}
    if len(stamps) < 2:
        raise LogError(path, f"the entries {', '.join(repr(pairs[k]) for k in pairs if k != 'state')} overlap in "
                       f"{len(stamps)} samples; a fit needs many")
    unit_pairs = []
    for quantity in ("q", "qd", "qdd"):
        if quantity in columns_raw:
            factor, unit, note = _in_joint_units(path, entries[pairs[quantity]], quantity, units,
                                                 entries.get(pairs.get("q", "")), flag)
            columns_raw[quantity] = columns_raw[quantity] * factor
            unit_pairs.append((quantity, unit))
            if note:
                notes.append(note)
    kinds = {unit == LINEAR_UNIT for _, unit in unit_pairs}
    if len(kinds) > 1:
        raise LogError(path, "the entries mix a length and an angle (" + ", ".join(
            f"{pairs[q]!r} in {entries[pairs[q]].unit or unit}" for q, unit in unit_pairs) + "); give them one "
            "unit with --units")
    linear = kinds == {True}
    if linear:
        sysid_notes.append(f"{pairs[base]!r} is a length: q is read in metres"
                           + (" and qd in m/s" if "qd" in columns_raw else "") + ", a linear coordinate (the "
                           "wheel or drum turns; the gains are per metre), never an angle.")
    runs: list = []
    left_out: list = []
    if "state" in pairs:
        state = series.get(pairs["state"])
        runs = run_names(test_runs(state.times, state.values, stamps) if state is not None else [])
        runs, left_out, said = _kept_runs(runs, stamps, repeats)
        sysid_notes += said
        if not runs:
            raise LogError(path, f"entry {pairs['state']!r} marks no test run ({', '.join(TESTS)}) of at least "
                           f"{MIN_RUN_SAMPLES} samples of {pairs[base]!r}")
    lag = None
    position_source = "logged"
    if base == "qd":
        position_source = "integrated velocity"
        columns_raw["q"] = _integrated(stamps, columns_raw.pop("qd"))
        unit_pairs.insert(0, ("q", dict(unit_pairs)["qd"]))
        sysid_notes.append(f"No position entry: q is the logged velocity {pairs['qd']!r} integrated (trapezoids), "
                           "so it is no absolute angle, and its derivatives are that velocity smoothed; the "
                           "velocity's lag behind the position cannot be checked without a position.")
    elif "qd" in columns_raw and "qdd" not in columns_raw:  # with qdd logged too, the fit takes both as logged
        segments = [rows for _, rows in runs] or [slice(0, len(stamps))]
        lag = velocity_lag(stamps * 1e-6, columns_raw["q"], columns_raw["qd"], segments)
        if lag is not None:
            sysid_notes.append(lag_note(pairs["qd"], lag))
    t = stamps * 1e-6  # the log's own seconds: log-info, windows, exclusions and messages share them
    columns = {"t": t, **{name: columns_raw[name] for name in ("q", "qd", "qdd", "tau") if name in columns_raw}}
    quantity_names = [(key, pairs[key]) for key in ("q", "qd", "qdd", "tau", "state") if key in pairs]
    if routine is not None:
        moves = (f"q from {shown_name(routine.position)}, " if routine.position else "") + \
            (f"qd from {shown_name(routine.velocity)}, " if routine.velocity else "")
        notes.insert(0, f"SysId routine {routine.routine!r}, motor {routine.motor!r}: {moves}effort from "
                     f"{shown_name(routine.voltage)} (volts), tests from {shown_name(routine.state)}.")
    if routine is not None and not routine.velocity:
        sysid_notes.append(f"Motor {routine.motor!r} logged no velocity: its lag cannot be checked.")
    table = WpilogTable(
        path=path, columns=columns, positions={name: i + 1 for i, name in enumerate(columns)}, ignored=(),
        segments=(), notes=tuple(notes) + tuple(sysid_notes), entries=tuple(quantity_names), stamps=stamps,
        units=tuple(unit_pairs), runs=tuple(runs), routine=routine, time_origin=0.0,
        read_as=tuple((key, "record time" if key == "t" else pairs.get(key, pairs.get("qd", key)))
                      for key in columns),
        position_source=position_source, velocity_lag_s=lag, left_out=tuple(left_out),
        sysid_notes=tuple(sysid_notes),
    )
    check_finite(table)
    return table


def _kept_runs(runs: list, stamps: np.ndarray, repeats: str) -> tuple[list, list, list]:
    """(the runs fitted, (run, why) of those left out, notes): runs too short to fit, and with repeats 'first'
    every run of a test after its first, are left out."""
    kept, left_out, notes = [], [], []
    seconds = lambda rows: f"t = {stamps[rows.start] * 1e-6:.6g} to {stamps[rows.stop - 1] * 1e-6:.6g} s"  # noqa
    tests: dict[str, list] = {}
    for name, rows in runs:
        tests.setdefault(name.partition(" #")[0], []).append((name, rows))
    for test, found in tests.items():
        if len(found) > 1:
            spans = ", ".join(f"{name} ({seconds(rows)})" for name, rows in found)
            use = ("each test's first run is fitted, as SysId's analysis does (--sysid-runs first)"
                   if repeats == "first" else "every run is fitted (SysId's analysis uses only the first: "
                   "--sysid-runs first does the same)")
            notes.append(f"{test} was run {len(found)} times, kept apart: {spans}; {use}.")
    first_seen: set = set()
    for name, rows in runs:
        test = name.partition(" #")[0]
        count = rows.stop - rows.start
        if repeats == "first" and test in first_seen:
            left_out.append((name, f"a repeat ({seconds(rows)}); --sysid-runs first fits each test's first run"))
        elif count < MIN_RUN_SAMPLES:
            left_out.append((name, f"too short to fit: {count} samples ({seconds(rows)}), fewer than "
                             f"{MIN_RUN_SAMPLES}"))
        else:
            kept.append((name, rows))
        first_seen.add(test)
    if left_out:
        notes.append("Left out: " + "; ".join(f"{name}, {why}" for name, why in left_out) + ".")
    return kept, left_out, notes


def _integrated(stamps: np.ndarray, velocity: np.ndarray) -> np.ndarray:
    """The position a velocity integrates to (trapezoids), nothing added across a gap between tests."""
    seconds = np.diff(stamps) * 1e-6
    steps = 0.5 * (velocity[1:] + velocity[:-1]) * seconds
    positive = seconds[seconds > 0]
    if len(positive):
        steps[seconds > RUN_GAP_STEPS * float(np.median(positive))] = 0.0
    return np.concatenate(([0.0], np.cumsum(steps)))


def _interpolated(other: Series, stamps: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(values of `other` interpolated linearly at `stamps`, True where it has records near enough): a record
    within NEAR_STEPS of its median step (the same loop), or records either side at most GAP_STEPS apart."""
    order = np.argsort(other.times, kind="stable")
    times, values = other.times[order].astype(float), other.values[order]
    at = stamps.astype(float)
    result = np.interp(at, times, values)
    steps = np.diff(times)
    positive = steps[steps > 0]
    median = float(np.median(positive)) if len(positive) else 0.0
    after = np.clip(np.searchsorted(times, at, side="left"), 0, len(times) - 1)
    before = np.clip(after - 1, 0, len(times) - 1)
    nearest = np.minimum(np.abs(times[after] - at), np.abs(at - times[before]))
    inside = (at >= times[0]) & (at <= times[-1])
    bracketed = inside & (times[after] - times[before] <= GAP_STEPS * median)
    return result, bracketed | (nearest <= NEAR_STEPS * median)


def _in_joint_units(path: str, entry: Entry, quantity: str, units: str | None, position: Entry | None, flag: str
                    ) -> tuple[float, str, str | None]:
    """(joint units per logged unit, the unit, a note) of the q, qd or qdd entry: radians for an angle, metres
    for a length; LogError when the unit is not known."""
    rate = quantity != "q"
    text = entry.unit
    unit, per = angle_unit(text, rate)
    metres = metres_per(text)
    if units == LINEAR_UNIT:
        if unit is not None:
            raise LogError(path, f"--units meters: entry {entry.name!r} is in {text!r}, an angle; leave --units "
                           "out to read it in radians")
        return 1.0, LINEAR_UNIT, (None if metres in (None, 1.0) else
                                  f"--units meters is read over the unit {text!r} of {entry.name!r}.")
    if units is not None:
        if metres is not None:
            raise LogError(path, f"--units {units}: entry {entry.name!r} is in {text!r}, a length, not an angle; "
                           "leave --units out (a length is read in metres: a drive's or an elevator's gains per "
                           "metre)")
        note = None
        if unit is not None and unit != units:
            note = (f"--units {units} is read over the unit {text!r} that the metadata of {entry.name!r} names.")
        return UNITS[units] * (per if unit == units else 1.0), units, note
    if unit is None and metres is None and text is None and rate and position is not None:
        # A velocity without a unit of its own is the position's per second (AdvantageKit logs units once).
        unit, _ = angle_unit(position.unit, False)
        if unit is not None:
            return UNITS[unit], unit, (f"{entry.name!r} names no unit; read in {unit} per second, as "
                                       f"{position.name!r}.")
        metres = metres_per(position.unit)
        if metres is not None:
            return metres, LINEAR_UNIT, (f"{entry.name!r} names no unit; read as {position.name!r}'s "
                                         f"{position.unit!r} per second.")
    if metres is not None:
        note = None if metres == 1.0 else (f"{entry.name!r} is in {text!r} (its metadata): {quantity} = "
                                           f"{metres:.6g} × the logged value, in metres.")
        return metres, LINEAR_UNIT, note
    if unit is None:
        said = "names no unit in its metadata" if text is None else f"is in {text!r}, which is no angle or length"
        raise LogError(path, f"entry {entry.name!r} {said}; say which with --units rotations, radians, degrees or "
                       "meters")
    factor = UNITS[unit] * per
    note = None
    if unit != "radians" or per != 1.0:
        note = (f"{entry.name!r} is in {text!r} (its metadata): {quantity} = {factor:.6g} × the logged value, "
                "in radians.")
    return factor, "radians" if unit == "radians" else unit, note


# ---------------------------------------------------------------------------------------------- log-info


@dataclass(frozen=True, eq=False)
class WpilogInfo:
    """What `jointid log-info` shows: every entry, and any SysId routine with its test runs."""

    path: str
    extra_header: str
    entries: tuple[Entry, ...]
    routines: tuple[SysIdRoutine, ...]
    lacking_voltage: tuple[str, ...]
    """Routines with a test-state entry but no voltage entry."""
    runs: dict
    """Routine -> ((test, start s, end s, state records), ...) in time order."""

    @property
    def duration(self) -> float:
        """Seconds from the first record of any entry to the last."""
        firsts = [e.first_us for e in self.entries if e.first_us is not None]
        lasts = [e.last_us for e in self.entries if e.last_us is not None]
        return (max(lasts) - min(firsts)) * 1e-6 if firsts else 0.0

    def named_runs(self, routine: str) -> list[tuple[tuple[str, int, int, int], str]]:
        """Each run of a routine's tests with its name ("quasistatic-forward #2" for a test run again)."""
        stretches = self.runs.get(routine, ())
        names = run_names([(test, slice(0, 0)) for test, *_ in stretches])
        return [(stretch, name) for stretch, (name, _) in zip(stretches, names)]

    @property
    def start_us(self) -> int:
        """The first record's time stamp (us), from which log-info counts times."""
        firsts = [e.first_us for e in self.entries if e.first_us is not None]
        return min(firsts) if firsts else 0

    def to_dict(self) -> dict:
        """The JSON document of `log-info --json` (times in seconds of the log's own time stamps)."""
        return {
            "path": self.path, "format": "wpilog", "extra_header": self.extra_header, "duration_s": self.duration,
            "time_base": "the data log's own time stamps (s), as --train-window and --exclude take them",
            "entries": [entry.to_dict() for entry in self.entries],
            "sysid": [{"routine": r.routine, "motor": r.motor, "state": r.state, "voltage": r.voltage,
                       "position": r.position, "velocity": r.velocity,
                       "runs": [{"test": test, "name": name, "start_s": a * 1e-6, "end_s": b * 1e-6,
                                 "state_records": n} for (test, a, b, n), name in self.named_runs(r.routine)]}
                      for r in self.routines],
            "sysid_without_voltage": list(self.lacking_voltage),
        }


def wpilog_info(path, *, progress=None, cancel=None) -> WpilogInfo:
    """Survey a data log: every entry's type, metadata, record count and times, and its SysId routines' runs;
    LogError if unreadable."""
    path = os.fspath(path)
    entries, series = read_entries(path, lambda name, kind: name.startswith(STATE_PREFIX) and kind == "string",
                                   count_all=True, progress=progress, cancel=cancel)
    routines, lacking = sysid_routines(entries)
    runs = {}
    for name, found in series.items():
        runs[name[len(STATE_PREFIX):]] = _state_stretches(found)
    return WpilogInfo(path, extra_header(path, open_reader(path)), tuple(entries.values()), tuple(routines),
                      tuple(lacking), runs)


def _state_stretches(series: Series) -> tuple[tuple[str, int, int, int], ...]:
    """(test, first us, last us, records) of each stretch of one of the TESTS in a state entry."""
    order = np.argsort(series.times, kind="stable")
    times, states = series.times[order], series.values[order]
    steps = np.diff(times)
    positive = steps[steps > 0]
    gap = RUN_GAP_STEPS * float(np.median(positive)) if len(positive) else math.inf
    out, start = [], 0
    for k in range(1, len(states) + 1):
        if k == len(states) or states[k] != states[start] or times[k] - times[k - 1] > gap:
            if states[start] in TESTS:
                out.append((str(states[start]), int(times[start]), int(times[k - 1]), k - start))
            start = k
    return tuple(out)


def has_numbers(info: WpilogInfo) -> bool:
    """True when any entry holds numbers."""
    return any(entry.numeric for entry in info.entries)
