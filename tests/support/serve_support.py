"""`jointid serve` in a subprocess, and a client that speaks to it as textual-serve's page does.

The page connects to `/ws?width=W&height=H`, sends JSON envelopes (`["stdin", keys]`, `["resize", {...}]`,
`["focus"]`, `["ping", data]`) and receives the terminal's raw output as binary frames and
`["deliver_file_start", key]` text frames, after which it fetches `/download/<key>`. The client renders the binary
frames with pyte, a terminal emulator, so a test reads the screen as a person would. Every wait is for an event (a
frame holding a text, the socket closing, a line of the server's log) under a generous overall deadline.
"""

from __future__ import annotations

import asyncio
import json
import os
import re
import resource
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import aiohttp
import pyte

DEADLINE = 60.0
"""Seconds any one awaited event may take on a loaded machine before the test fails."""

KEYS = {"ctrl+s": "\x13", "ctrl+r": "\x12", "ctrl+o": "\x0f", "ctrl+u": "\x15", "enter": "\r", "escape": "\x1b", "end": "\x1b[F"}
"""The bytes a browser's terminal sends for the keys the tests press."""


def free_port() -> int:
    """A TCP port nothing listens on now on 127.0.0.1."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


class ServedExplorer:
    """`jointid serve` running in a subprocess on a free port; its log lines are read as they come."""

    def __init__(self, *flags: str, open_files: int | None = None) -> None:
        """Start `jointid serve --port PORT *flags`; with `open_files`, under that limit of open files (soft and
        hard, so the server cannot raise it)."""
        self.port = free_port()

        def limit_open_files() -> None:
            if open_files is not None:
                resource.setrlimit(resource.RLIMIT_NOFILE, (open_files, open_files))

        self.process = subprocess.Popen(
            [sys.executable, "-m", "jointid", "serve", "--port", str(self.port), *flags],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1,
            env={**os.environ, "PYTHONUNBUFFERED": "1"}, preexec_fn=limit_open_files,
        )
        self.lines: list[str] = []
        self.changed = threading.Condition()
        threading.Thread(target=self._read_log, daemon=True).start()
        try:
            self.wait_for_line(re.escape("Press Ctrl+C to stop."))
        except BaseException:
            self.stop()  # a server that did not start is not left running
            raise

    def _read_log(self) -> None:
        """Collect the server's output lines as they come (a thread: a pipe's buffered reads defeat select)."""
        for line in self.process.stdout:
            with self.changed:
                self.lines.append(line)
                self.changed.notify_all()
        with self.changed:
            self.lines.append("")  # the end of the output
            self.changed.notify_all()

    @property
    def url(self) -> str:
        """The server's address."""
        return f"http://127.0.0.1:{self.port}"

    def wait_for_line(self, pattern: str, start: int = 0) -> re.Match:
        """The first log line from index `start` on matching the regular expression `pattern`, waiting for it."""
        return self.wait_for_lines(pattern, 1, start)[0]

    def wait_for_lines(self, pattern: str, count: int, start: int = 0) -> list[re.Match]:
        """The first `count` log lines from index `start` on matching `pattern`, waiting for them."""
        deadline = time.monotonic() + DEADLINE
        found: list[re.Match] = []
        index = start
        with self.changed:
            while True:
                while index < len(self.lines) and len(found) < count:
                    assert self.lines[index], "the server ended; it said:\n" + "".join(self.lines)
                    match = re.search(pattern, self.lines[index])
                    if match:
                        found.append(match)
                    index += 1
                if len(found) == count:
                    return found
                left = deadline - time.monotonic()
                assert left > 0, f"not {count} lines matching {pattern!r}; the server said:\n" + "".join(self.lines)
                self.changed.wait(left)

    def session_ended(self, pid: int, start: int = 0) -> None:
        """Wait for the server's line saying session `pid` ended."""
        self.wait_for_line(rf"session ended: pid {pid}\b", start)

    def stop(self) -> None:
        """End the server (SIGTERM, as a service manager would) and wait for it."""
        self.process.terminate()
        try:
            self.process.wait(DEADLINE)
        finally:
            if self.process.poll() is None:
                self.process.kill()
            self.process.stdout.close()


def run(scenario):
    """Run an async scenario with one HTTP client session."""

    async def main():
        async with aiohttp.ClientSession() as http:
            return await scenario(http)

    return asyncio.run(main())


def path_field(tab: BrowserTerminal) -> str:
    """What the Open dialog's path field shows (the line under its label, left of any notification)."""
    lines = tab.screen.display
    label = next(index for index, line in enumerate(lines) if "Path (Enter opens it):" in line)
    start = lines[label].index("Path")
    return lines[label + 1][start:].split("▌")[0].split("│")[0].strip()


def disposition_name(response: aiohttp.ClientResponse) -> str:
    """The file name a browser saves a download as: its Content-Disposition's `filename*` (RFC 6266), else
    `filename`, read by aiohttp's parser of the header."""
    from aiohttp.multipart import content_disposition_filename, parse_content_disposition

    _, fields = parse_content_disposition(response.headers["Content-Disposition"])
    return content_disposition_filename(fields, "filename")


def process_alive(pid: int) -> bool:
    """Whether process `pid` exists and has not ended (a zombie counts as ended)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except FileNotFoundError:
        return False
    return "State:\tZ" not in status


class BrowserTerminal:
    """One browser tab's connection: keys in, the screen out through pyte, downloads fetched as the page would."""

    def __init__(self, http: aiohttp.ClientSession, server: ServedExplorer, width: int = 80, height: int = 24,
                 render: bool = True):
        """With `render` False the frames are only kept as bytes (`received`), not drawn: a benchmark's client
        timing 20 tabs must not spend the time it measures in a terminal emulator written in Python."""
        self.render = render
        self.received = bytearray()
        self.http = http
        self.server = server
        self.width, self.height = width, height
        self.screen = pyte.Screen(width, height)
        self.stream = pyte.ByteStream(self.screen)
        self.socket: aiohttp.ClientWebSocketResponse | None = None
        self.deliveries: list[str] = []
        self.closed = False
        self.close_reason: tuple = ()
        self.changed = asyncio.Event()
        self.reader: asyncio.Task | None = None

    async def connect(self, focus: bool = True, origin: str | None = None) -> BrowserTerminal:
        """Open the WebSocket as the page does (and give the terminal focus, as a click on the page does); with
        `origin`, as a page from that origin does (a browser sends it with every WebSocket)."""
        self.socket = await self.http.ws_connect(f"{self.server.url}/ws?width={self.width}&height={self.height}",
                                                 origin=origin)
        self.reader = asyncio.create_task(self._read())
        await self.send(["resize", {"width": self.width, "height": self.height}])
        if focus:
            await self.send(["focus"])
        return self

    async def send(self, envelope: list) -> None:
        """Send one JSON envelope."""
        await self.socket.send_str(json.dumps(envelope))

    async def press(self, *keys: str) -> None:
        """Type keys: names from KEYS, or text as it is."""
        for key in keys:
            await self.send(["stdin", KEYS.get(key, key)])

    @property
    def text(self) -> str:
        """The screen's lines as shown now."""
        return "\n".join(self.screen.display)

    @property
    def notices(self) -> str:
        """The text right of the rightmost half-block on each line (where Textual's toasts have their edge),
        the lines joined: a notification's message as one string, however the toast wraps it."""
        parts = [line[line.rfind("▌") + 1:] for line in self.screen.display if "▌" in line]
        return " ".join(" ".join(parts).split())

    async def _read(self) -> None:
        """Take every frame as it comes (so the server's pings are answered): draw it, note a delivery, or note
        the close; wake whoever waits."""
        while True:
            message = await self.socket.receive()
            if message.type == aiohttp.WSMsgType.BINARY:
                if self.render:
                    self.stream.feed(message.data)
                else:
                    self.received += message.data
            elif message.type == aiohttp.WSMsgType.TEXT:
                kind, data = json.loads(message.data)
                if kind == "deliver_file_start":
                    self.deliveries.append(data)
            else:  # CLOSE, CLOSING, CLOSED or ERROR: the connection is over
                self.closed = True
                self.close_reason = self.socket.close_code, message.extra or ""
            self.changed.set()
            if self.closed:
                return

    async def wait_until(self, condition, what: str, timeout: float = DEADLINE) -> None:
        """Wait until `condition()` holds, checked as each frame arrives; fail naming `what` after `timeout`
        seconds, or if the connection closes first."""
        deadline = time.monotonic() + timeout
        while not condition():
            left = deadline - time.monotonic()
            if left <= 0 or self.closed:
                raise AssertionError(f"waited for {what}; the screen shows:\n{self.text}\nclosed: {self.closed} "
                                     f"{self.close_reason}")
            self.changed.clear()
            if condition():
                return
            try:
                await asyncio.wait_for(self.changed.wait(), left)
            except TimeoutError:
                pass

    async def wait_for_text(self, text: str, timeout: float = DEADLINE) -> None:
        """Wait until the screen shows `text`."""
        await self.wait_until(lambda: text in self.text, repr(text), timeout)

    async def press_until_text(self, key: str, text: str, timeout: float = DEADLINE) -> None:
        """Press `key` until the screen shows `text`: a key that scrolls a screen still laying out its text (the
        help's Markdown is laid out after its first paint) can land before there is anywhere to scroll."""
        deadline = time.monotonic() + timeout
        while True:
            await self.press(key)
            try:
                await self.wait_for_text(text, timeout=min(2.0, max(deadline - time.monotonic(), 0.0)))
                return
            except AssertionError:
                if time.monotonic() >= deadline or self.closed:
                    raise

    async def wait_for_close(self, timeout: float = DEADLINE) -> None:
        """Wait until the server closes the connection."""
        deadline = time.monotonic() + timeout
        while not self.closed:
            assert time.monotonic() < deadline, f"the server did not close the connection; screen:\n{self.text}"
            self.changed.clear()
            try:
                await asyncio.wait_for(self.changed.wait(), deadline - time.monotonic())
            except TimeoutError:
                pass

    async def download(self, key: str) -> tuple[str, str, bytes]:
        """Fetch a delivery as the page does: its file name, content type and bytes."""
        async with self.http.get(f"{self.server.url}/download/{key}") as response:
            assert response.status == 200, await response.text()
            return disposition_name(response), response.headers["Content-Type"], await response.read()

    async def close(self) -> None:
        """Close the connection as a browser closing the tab does."""
        await self.socket.close()
        if self.reader is not None:
            await self.reader
