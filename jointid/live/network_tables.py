"""A joint watched over NetworkTables 4, the protocol robot code and WPILib's simulator publish to, through
pyntcore (the optional extra `jointid[nt]`, imported only here and only when a source is opened).

The topics are named as a data log's entries are (`--entry q=/Arm/Position,tau=/Arm/Voltage`, with qd, qdd and a
SysId test-state string topic `state=`). Every value is asked for (sendAll, keepDuplicates) and taken with its
time stamp on the server's clock as ntcore's listener thread hands it over; values and connection events arrive
there in order, so a reconnection falls exactly between the values before and after it. The topics are put on one
time base as a data log's entries are (live.alignment). Units come from each topic's "unit" property, read as a
data log's metadata (rotations, degrees, metres, ...); without one the angle is read in radians, and said so.

What can go wrong says so in one line (NetworkTablesError): a host that does not answer, a topic that the server
does not publish after a short wait, a topic of the wrong type. A server that goes and returns is reconnected:
the gap is an event and a new stretch starts (nothing is interpolated across it). Values that arrive faster than
they are polled are held up to a bound, and the rest counted as dropped.
"""

from __future__ import annotations

import json
import threading
import time
import weakref
from collections import deque

import numpy as np

from ..logs.conventions import ColumnMapError, EntryMap
from ..logs.table import LogError
from ..logs.wpilog import Entry, LINEAR_UNIT, UNIT_CHOICES, _in_joint_units, unit_text
from .alignment import TopicAligner
from .reading import LiveReading
from .received import Received
from .stretches import StretchClock
from .integration import VelocityIntegral
from .unwrapping import LiveUnwrap

DEFAULT_PORT = 5810
"""NetworkTables 4's port."""

EXTRA_HINT = "watching NetworkTables needs the optional pyntcore package: pip install 'jointid[nt]'"
"""The one line shown when pyntcore is not installed."""

NUMERIC_TYPES = ("double", "float", "int")
"""Topic types read as numbers."""

BUFFERED_VALUES = 1 << 20
"""Values held between two polls; more are dropped and counted (about 4 minutes of four topics at 1 kHz)."""

SEND_PERIOD = 0.02
"""Seconds between the server's sends of queued values (ntcore's default 0.1 s would make refreshes lag)."""

VOLT_WORDS = ("v", "volt", "volts")
"""Unit property values that make the effort a voltage."""


class NetworkTablesError(ValueError):
    """A NetworkTables source that cannot be watched; str() is one line."""


def parse_address(text) -> tuple[str, int]:
    """(host, port) of 'HOST[:PORT]' (port 5810 when not given; '[::1]:5810' for IPv6), or of a (host, port) pair
    already parsed; NetworkTablesError."""
    if isinstance(text, tuple) and len(text) == 2:
        text = f"[{text[0]}]:{text[1]}" if ":" in str(text[0]) else f"{text[0]}:{text[1]}"
    given = str(text).strip()
    host, port = given, DEFAULT_PORT
    if given.startswith("["):
        close = given.find("]")
        host, rest = given[1:close] if close > 0 else "", given[close + 1:] if close > 0 else ""
        if rest:
            port = _port(given, rest.removeprefix(":"))
    elif given.count(":") == 1:
        host, number = given.split(":")
        port = _port(given, number)
    if not host:
        raise NetworkTablesError(f"--nt {given!r}: give the server's HOST[:PORT], e.g. 127.0.0.1 or 10.12.34.2:5810")
    return host, port


def _port(given: str, number: str) -> int:
    """The port number in `number`; NetworkTablesError unless it is 1-65535."""
    if not number.strip().isdigit() or not 0 < int(number) < 65536:
        raise NetworkTablesError(f"--nt {given!r}: port {number!r} is not a number from 1 to 65535")
    return int(number)


def _ntcore():
    """The ntcore module; NetworkTablesError (one line) when pyntcore is not installed."""
    try:
        import ntcore
    except ImportError:
        raise NetworkTablesError(EXTRA_HINT) from None
    return ntcore


class NetworkTablesSource:
    """A live source of NetworkTables 4 topics (see the module's notes)."""

    def __init__(self, address: str, entries, *, reading: LiveReading | None = None, units: str | None = None,
                 connect_timeout: float = 5.0, topic_timeout: float = 2.0, duration: float | None = None,
                 gone_timeout: float | None = None, buffered_values: int = BUFFERED_VALUES,
                 client_name: str = "jointid watch"):
        """Connect to the server at `address` ('HOST[:PORT]', or a (host, port) pair) and subscribe to the topics
        `entries` names (an EntryMap, 'q=/Arm/Position,tau=/Arm/Voltage' or a mapping); NetworkTablesError when
        the server does not answer within `connect_timeout` s, a topic is not published within `topic_timeout` s
        after that, or one has the wrong type. `units` reads every angle topic in that unit over its properties
        ('rotations', 'radians', 'degrees', 'meters'); `duration` ends the source after that many seconds of samples,
        `gone_timeout` after the server has been gone that many seconds (None: it is waited for)."""
        self.host, self.port = parse_address(address)
        self.where = f"NetworkTables {self.host}:{self.port}"
        try:
            self.entries = entries if isinstance(entries, EntryMap) else EntryMap.of(entries, "--entry")
        except ColumnMapError as error:
            raise NetworkTablesError(str(error)) from None
        if self.entries is None:
            raise NetworkTablesError(f"--entry: name the topics, e.g. --entry {EntryMap.EXAMPLE}")
        self.pairs = dict(self.entries.pairs)
        if "q" not in self.pairs and "qd" not in self.pairs:
            raise NetworkTablesError(f"--entry names no topic for q or qd; jointid needs the joint's position "
                                     f"(q=TOPIC) or its velocity (qd=TOPIC)")
        if "tau" not in self.pairs:
            raise NetworkTablesError("--entry names no topic for tau; jointid needs its effort (tau=TOPIC, a "
                                     "voltage or torque)")
        if units is not None and units not in UNIT_CHOICES:
            raise NetworkTablesError(f"--units {units!r}: give one of {', '.join(UNIT_CHOICES)}")
        self.units, self.duration, self.gone_timeout = units, duration, gone_timeout
        self.reading = reading or LiveReading()
        self.buffered_values = int(buffered_values)
        self.description = f"{self.where}: " + ", ".join(f"{key}={name}" for key, name in self.entries.pairs)
        self.ntcore = _ntcore()
        self.lock = threading.Condition()
        self.incoming: deque = deque()
        self.dropped = 0
        self.events: list[str] = []
        self.connected = False
        self.instance = None
        self.listeners: list[int] = []
        try:
            self._start(client_name)
            self._await_connection(connect_timeout)
            self._await_topics(topic_timeout)
            self._read_units()
        except BaseException:
            self.close()
            raise
        self.numeric = tuple(key for key in ("q", "qd", "qdd", "tau") if key in self.pairs)
        self.aligner = TopicAligner(self.numeric, "q" if "q" in self.pairs else "qd", "state" in self.pairs)
        self.clock = StretchClock()
        self.unwrapping = LiveUnwrap()
        self.integral = VelocityIntegral()
        if "q" not in self.pairs:
            self.events.append(f"No position topic: q is the velocity {self.pairs['qd']!r} integrated (trapezoids), "
                               "so it is no absolute angle, and its derivatives are that velocity smoothed.")
        self.first_t: float | None = None
        self.ended = False
        self.last_seen: dict[str, tuple[int, object]] = {}
        self.skip_repeat: set[str] = set()
        self.gone_at: float | None = None

    # -------------------------------------------------------------------------------------- connecting

    def _start(self, client_name: str) -> None:
        """A client instance subscribed to every topic named (before connecting, so no early value is missed)."""
        nt = self.ntcore
        self.instance = nt.NetworkTableInstance.create()
        # The subscribers live only in this dict, which _release empties before the instance goes; what has a close
        # is closed then.
        self.subscribers: dict[str, object] = {}
        closing: list = []
        self._release = weakref.finalize(self, _release, nt, self.instance, self.listeners, self.subscribers,
                                         closing)
        options = nt.PubSubOptions(sendAll=True, keepDuplicates=True, periodic=SEND_PERIOD)
        self.topics = {key: self.instance.getTopic(name) for key, name in self.pairs.items()}
        self.subscribers.update({key: topic.genericSubscribe(options) for key, topic in self.topics.items()})
        # Topics only, for messages that list what the server publishes.
        self.every_topic = nt.MultiSubscriber(self.instance, ["/"], nt.PubSubOptions(topicsOnly=True))
        closing.append(self.every_topic)
        flags = nt.EventFlags
        for key, subscriber in self.subscribers.items():
            self.listeners.append(self.instance.addListener(subscriber, flags.kValueAll, self._listener(key)))
        self.listeners.append(self.instance.addConnectionListener(True, self._on_connection))
        self.instance.setServer(self.host, self.port)
        self.instance.startClient4(client_name)

    def _listener(self, quantity: str):
        """The callback ntcore's listener thread calls with each value of `quantity`'s topic: queued (or counted as
        dropped when the buffer is full). It runs once per value, so it does no more than that."""
        incoming, lock, limit = self.incoming, self.lock, self.buffered_values

        def on_value(event) -> None:
            value = event.data.value
            with lock:
                if len(incoming) >= limit:
                    self.dropped += 1
                    return
                incoming.append(("value", quantity, value.server_time(), value.value()))
                lock.notify()

        return on_value

    def _on_connection(self, event) -> None:
        """ntcore's listener thread: connected or disconnected, queued in order with the values."""
        up = bool(event.flags & self.ntcore.EventFlags.kConnected)
        with self.lock:
            self.connected = up
            self.incoming.append(("connected" if up else "disconnected", time.monotonic()))
            self.lock.notify_all()

    def _await_connection(self, timeout: float) -> None:
        """Wait until connected; NetworkTablesError when the server does not answer in time."""
        with self.lock:
            if not self.lock.wait_for(lambda: self.connected, timeout=timeout):
                raise NetworkTablesError(f"{self.where}: no NetworkTables server answered in {timeout:g} s (is the "
                                         "robot or the simulator running, and is the address right?)")

    def _await_topics(self, timeout: float) -> None:
        """Wait until the server announces every topic named; NetworkTablesError naming a missing one or one of
        the wrong type."""
        deadline = time.monotonic() + timeout
        while not all(topic.exists() for topic in self.topics.values()) and time.monotonic() < deadline:
            time.sleep(0.01)  # announcements raise no event on these subscribers; they come within a few sends
        for key, topic in self.topics.items():
            if not topic.exists():
                published = sorted(info.name for info in self.instance.getTopicInfo() if not info.name.startswith("$"))
                shown = ", ".join(published[:20]) + (", …" if len(published) > 20 else "")
                raise NetworkTablesError(f"{self.where}: --entry {key}={topic.getName()}: the server publishes no "
                                         f"topic {topic.getName()!r} (waited {timeout:g} s); it publishes "
                                         f"{shown or 'no topics'}")
            kind = topic.getTypeString()
            wanted = "string" if key == "state" else "a number (double, float or int)"
            if (key == "state") != (kind == "string") or (key != "state" and kind not in NUMERIC_TYPES):
                raise NetworkTablesError(f"{self.where}: --entry {key}={topic.getName()}: topic "
                                         f"{topic.getName()!r} holds {kind}, not {wanted}")

    def _read_units(self) -> None:
        """Each angle topic's factor to radians (or metres) from its unit property (or --units), and the effort's
        kind: a SysId test-state topic, or a tau whose unit is volts, makes it a voltage."""
        units = {key: self._unit(topic) for key, topic in self.topics.items()}
        motion = [key for key in ("q", "qd", "qdd") if key in self.pairs]
        self.factors: dict[str, float] = {}
        self.linear = False
        if self.units is None and not any(units[key] for key in motion):
            self.events.append(f"{', '.join(self.pairs[key] for key in motion)} publish no unit property: read in "
                               "radians (give --units rotations, degrees or meters if they are not)")
            self.factors = {key: 1.0 for key in motion}
        else:
            position = self._entry("q", units) if "q" in self.pairs else None
            kinds = set()
            for key in motion:
                try:
                    factor, unit, note = _in_joint_units(self.where, self._entry(key, units), key, self.units,
                                                         position, "--entry")
                except LogError as error:
                    raise NetworkTablesError(f"{self.where}: {error.problem.replace('metadata', 'unit property')}"
                                             ) from None
                self.factors[key] = factor
                kinds.add(unit == LINEAR_UNIT)
                if note is None:
                    how = f"--units {self.units}" if self.units else "its unit property"
                    note = f"{self.pairs[key]!r} is read in {unit} ({how})."
                self.events.append(note.replace("(its metadata)", "(its unit property)"))
            if len(kinds) > 1:
                raise NetworkTablesError(f"{self.where}: the topics mix a length and an angle; give them one unit "
                                         "with --units")
            self.linear = kinds == {True}
        reading = self.reading
        volts = (units.get("tau") or "").lower() in VOLT_WORDS
        if reading.effort.kind == "torque" and ("state" in self.pairs or volts):
            why = "a SysId test-state topic is named" if "state" in self.pairs else "its unit is volts"
            self.events.append(f"tau ({self.pairs['tau']}) is read as motor voltage: {why}.")
            reading = reading.with_effort_kind("voltage")
        self.reading = reading
        self.effort = reading.effort_kind
        self.events.extend(reading.notes())

    def _unit(self, topic) -> str | None:
        """A topic's "unit" (or "units") property, or None."""
        try:
            properties = topic.getProperties()
        except Exception:  # a server's malformed properties: as if none were published
            return None
        found = properties.get("unit", properties.get("units")) if isinstance(properties, dict) else None
        if found is None:
            return None
        text = str(found).strip()
        if text.startswith('"'):  # the JSON text of a string, as robot code sets it
            try:
                text = str(json.loads(text))
            except ValueError:
                pass
        return unit_text(text)

    def _entry(self, key: str, units: dict) -> Entry:
        """A data log's Entry standing for the topic of `key`, so that its unit is read as a log's is."""
        unit = units.get(key)
        return Entry(0, self.pairs[key], "double", "" if unit is None else json.dumps({"unit": unit}))

    # -------------------------------------------------------------------------------------- polling

    def poll(self, timeout: float) -> Received:
        """Wait up to `timeout` seconds for values, then return the rows they complete (maybe none)."""
        if self.ended:
            return Received(ended=True)
        with self.lock:
            self.lock.wait_for(lambda: self.incoming, timeout=max(timeout, 0.0))
            items = list(self.incoming)
            self.incoming.clear()
            dropped, self.dropped = self.dropped, 0
        parts: list[dict] = []
        breaks: list[int] = []
        left_out = 0

        def take(final: bool = False) -> None:
            """Rows the aligner has ready, placed on the session's time (a new stretch's first row marked)."""
            nonlocal left_out
            columns, lost = self.aligner.take(final)
            left_out += lost
            if not columns or not len(columns["t"]):
                return
            if self.clock.starting:
                breaks.append(sum(len(part["t"]) for part in parts))
                self.unwrapping.restart()
                self.integral.restart()
            columns = self.reading.convert(columns, self.factors)
            if "q" not in columns:
                columns = {"t": columns["t"], "q": self.integral.position(columns["t"], columns["qd"]),
                           **{name: column for name, column in columns.items() if name != "t"}}
            if "q" in columns and not self.linear:
                columns["q"], wrapped = self.unwrapping.unwrap(columns["t"], columns["q"])
                if wrapped:
                    self.events.append(wrapped)
            columns["t"], said = self.clock.place(columns["t"])
            if said:
                self.events.append(said)
            parts.append(columns)

        for item in items:
            if item[0] == "value":
                self._add_value(*item[1:])
            elif item[0] == "disconnected":
                take(final=True)  # what the stretch completes; nothing waits across the gap
                self.aligner.clear()
                self.gone_at = item[1]
                shown = "" if self.clock.last is None else f" at {self.clock.last:.1f} s"
                self.events.append(f"source gone{shown}: the server disconnected")
            elif item[0] == "connected":
                if self.gone_at is not None:
                    gap = item[1] - self.gone_at
                    self.events.append(f"reconnected after a {gap:.1f} s gap (not bridged)")
                    self.clock.new_stretch(gap)
                    self.skip_repeat = set(self.last_seen)
                    self.gone_at = None
                else:
                    self.events.append(f"connected to {self.host}:{self.port}")
        take()
        if self.gone_at is not None and self.gone_timeout is not None and \
                time.monotonic() - self.gone_at >= self.gone_timeout:
            self.events.append(f"the server has been gone for {self.gone_timeout:g} s: done")
            self.ended = True
        return self._received(parts, tuple(breaks), dropped, left_out)

    def _add_value(self, quantity: str | None, stamp: int, value) -> None:
        """One value for the aligner (a server's current value re-sent on reconnecting is skipped)."""
        if quantity is None or value is None:
            return  # a topic's first, empty value
        if quantity in self.skip_repeat:
            self.skip_repeat.discard(quantity)
            if self.last_seen.get(quantity) == (stamp, value):
                return
        if (quantity == "state") != isinstance(value, str) or (quantity != "state" and isinstance(value, bool)):
            raise NetworkTablesError(f"{self.where}: topic {self.pairs[quantity]!r} ({quantity}) now holds "
                                     f"{type(value).__name__} values, not "
                                     f"{'text' if quantity == 'state' else 'numbers'}")
        self.last_seen[quantity] = (stamp, value)
        self.aligner.add(quantity, stamp * 1e-6, value if quantity == "state" else float(value))

    def _received(self, parts: list[dict], breaks: tuple[int, ...], dropped: int, left_out: int) -> Received:
        """One Received block of the rows taken (cut at `duration`, which ends the source)."""
        joined = {}
        if parts:
            joined = {name: np.concatenate([part[name] for part in parts]) for name in parts[0]}
            if self.first_t is None:
                self.first_t = float(joined["t"][0])
            if self.duration is not None and float(joined["t"][-1]) - self.first_t >= self.duration:
                keep = int(np.searchsorted(joined["t"], self.first_t + self.duration, side="right"))
                joined = {name: column[:keep] for name, column in joined.items()}
                breaks = tuple(row for row in breaks if row < keep)
                self.events.append(f"{self.duration:g} s of samples received: done")
                self.ended = True
        if left_out:
            self.events.append(f"{left_out} samples left out: another topic had no value near them")
        events, self.events = tuple(self.events), []
        return Received(columns=joined, events=events, dropped=dropped, ended=self.ended, breaks=breaks)

    def close(self) -> None:
        """Stop listening and close the connection."""
        self.ended = True
        if self.instance is not None:
            self._release()
            self.instance = None


def _release(ntcore, instance, listeners: list, subscribers: dict, closing: list) -> None:
    """Remove the listeners, unsubscribe and destroy the client: at close, or at exit for a source never closed
    (ntcore's listener thread calling into Python while the interpreter shuts down aborts the process).

    The subscribers go first: ntcore reuses a destroyed instance's handles for the next instance, so a subscriber
    freed after its instance would unsubscribe whichever subscriber of a later source now has its handle (that
    source then waited for topics that never came)."""
    for handle in listeners:
        instance.removeListener(handle)
    listeners.clear()
    subscribers.clear()  # a GenericSubscriber unsubscribes when freed (it has no close)
    for subscriber in closing:  # a MultiSubscriber
        subscriber.close()
    closing.clear()
    instance.stopClient()
    ntcore.NetworkTableInstance.destroy(instance)
