"""NetworkTables 4 on loopback for the live-source tests: a server started in the test process on 127.0.0.1 (a free
port) and a simulated joint's samples published to it with explicit time stamps on a simulated clock, faster than
real time."""

from __future__ import annotations

import json
import socket
import threading
import time

import ntcore

CLOCK_START = 1.0
"""Seconds the simulated clock starts at (ntcore takes a time stamp of 0 as 'now')."""


def free_port() -> int:
    """A TCP port nothing on 127.0.0.1 listens on now."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def wait_until(condition, timeout: float = 10.0, what: str = "the condition") -> None:
    """Return once `condition()` is true; AssertionError after `timeout` s (only a failing test waits that long)."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError(f"waited {timeout:g} s for {what}")
        time.sleep(0.002)


class LoopbackServer:
    """An NT4 server on 127.0.0.1:`port`, with publishers for a joint's topics."""

    def __init__(self, tmp_path, port: int | None = None):
        self.tmp_path = tmp_path
        self.instance = None
        for attempt in range(3 if port is None else 1):
            self.port = free_port() if port is None else port
            if self._start():
                break
        else:
            raise AssertionError(f"no NT4 server of this test's own came up on 127.0.0.1 (last tried {self.port})")
        self.publishers: dict[str, object] = {}
        self.meta: dict[str, object] = {}
        self.streams: list[threading.Thread] = []
        self.stopping = threading.Event()
        self.options = ntcore.PubSubOptions(sendAll=True, keepDuplicates=True)

    def _start(self) -> bool:
        """Start the server on self.port; True once a client sees this server's own marker topic there (a port
        another process took between free_port's probe and the server's bind would show another server's)."""
        self.instance = ntcore.NetworkTableInstance.create()
        self.instance.startServer(persist_filename=str(self.tmp_path / f"nt-{self.port}.json"),
                                  listen_address="127.0.0.1", port3=0, port4=self.port)
        wait_until(self._listening, what=f"the server to listen on port {self.port}")
        marker = f"/jointid-loopback/{id(self)}-{self.port}"
        marking = self.instance.getIntegerTopic(marker).publish()
        marking.set(1)
        probe = ntcore.NetworkTableInstance.create()
        try:
            probe.setServer("127.0.0.1", self.port)
            probe.startClient4("loopback probe")
            seen = probe.getTopic(marker)
            # A client hears only of topics it subscribes to, and only while the subscriber object lives.
            watching = seen.genericSubscribe(ntcore.PubSubOptions())
            try:
                wait_until(lambda: watching.exists(), timeout=30.0, what="the server's marker topic")
                return True
            except AssertionError:
                marking.close()
                self.instance.stopServer()
                ntcore.NetworkTableInstance.destroy(self.instance)
                self.instance = None
                return False
            finally:
                # Freed before its instance: ntcore hands a destroyed instance's handles to the next one.
                del watching
        finally:
            marking.close()
            probe.stopClient()
            ntcore.NetworkTableInstance.destroy(probe)

    @property
    def address(self) -> str:
        return f"127.0.0.1:{self.port}"

    def _listening(self) -> bool:
        try:
            with socket.create_connection(("127.0.0.1", self.port), timeout=0.2):
                return True
        except OSError:
            return False

    def publish_topics(self, topics: dict[str, str], units: dict[str, str] | None = None) -> None:
        """Publish `topics` ({name: 'double' or 'string'}), each with its "unit" property from `units` (JSON text,
        as robot code sets it)."""
        for name, kind in topics.items():
            topic = self.instance.getStringTopic(name) if kind == "string" else self.instance.getDoubleTopic(name)
            self.publishers[name] = topic.publish(self.options)
            if units and name in units:
                topic.setProperty("unit", json.dumps(units[name]))

    def subscribed(self, name: str) -> bool:
        """True once some client's subscription to topic `name` has reached the server (its $sub$ meta-topic)."""
        if name not in self.meta:
            self.meta[name] = self.instance.getTopic(f"$sub${name}").genericSubscribe(ntcore.PubSubOptions())
        value = self.meta[name].get().value()
        return value not in (None, b"\x90")  # msgpack's empty list: nobody subscribed yet

    def stream(self, columns: dict[str, tuple[str, object]], times, speedup: float = 20.0,
               batch: int = 50) -> threading.Thread:
        """Start a thread publishing each row of `columns` ({topic: values}) at time stamp CLOCK_START + `times`
        (s), `speedup` times faster than real time, flushing every `batch` rows; the thread is returned started."""
        stamps = [int(round((CLOCK_START + t) * 1e6)) for t in times]

        def run():
            began = time.monotonic()
            for row, stamp in enumerate(stamps):
                if self.stopping.is_set():
                    return
                for name, values in columns.items():
                    value = values[row]
                    self.publishers[name].set(value if isinstance(value, str) else float(value), stamp)
                if row % batch == batch - 1 or row == len(stamps) - 1:
                    self.instance.flush()
                    ahead = began + (stamps[row] - stamps[0]) * 1e-6 / speedup - time.monotonic()
                    if ahead > 0:
                        time.sleep(ahead)  # pacing of the simulated clock, not a test's wait

        thread = threading.Thread(target=run, daemon=True)
        thread.start()
        self.streams.append(thread)
        return thread

    def stop(self) -> None:
        """Stop the server (its clients see it go)."""
        self.stopping.set()
        for thread in self.streams:
            thread.join()
        if self.instance is not None:
            # Publishers and subscribers go before their instance (whose handles the next instance reuses).
            for publisher in self.publishers.values():
                publisher.close()
            self.publishers.clear()
            self.meta.clear()
            self.instance.stopServer()
            ntcore.NetworkTableInstance.destroy(self.instance)
            self.instance = None
