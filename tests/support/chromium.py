"""Headless Chromium driven through the DevTools protocol (CDP) over aiohttp's WebSocket client, no extra package.

Chromium is Debian's package (`.ci/run` installs it in CI). The browser is started with a new profile folder
and `--remote-debugging-port=0`; it prints the DevTools address it chose on stderr, and the page's own
WebSocket address is read from its `/json` list.
"""

from __future__ import annotations

import asyncio
import itertools
import json
import os
import re
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import aiohttp
import pytest

CHROMIUM = "/usr/bin/chromium"

FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--remote-debugging-port=0")
"""Flags that work on this machine's kind (and in CI, which runs as root: --no-sandbox)."""

RECORD_FRAMES = """
window.terminalText = "";
window.terminalWaiters = [];
window.terminalSockets = [];
const PageWebSocket = window.WebSocket;
window.WebSocket = class extends PageWebSocket {
  constructor(...args) {
    super(...args);
    window.terminalSockets.push(this);
    const decoder = new TextDecoder();
    this.addEventListener("message", (event) => {
      if (typeof event.data === "string") return;
      window.terminalText += decoder.decode(event.data, {stream: true});
      window.terminalWaiters = window.terminalWaiters.filter(([text, resolve]) => {
        if (!window.terminalText.includes(text)) return true;
        resolve(true);
        return false;
      });
    });
  }
};
window.terminalShows = (text) => window.terminalText.includes(text) ? Promise.resolve(true)
  : new Promise((resolve) => window.terminalWaiters.push([text, resolve]));
"""
"""Runs before the page's scripts: keeps the terminal output the page receives and its sockets
(`terminalSockets`), and `terminalShows(text)` resolves once the output holds `text` (an event, not a poll)."""

PAINTED = "new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(() => resolve(true))))"
"""Resolves after the browser has drawn two frames: the canvas shows what the terminal received."""

START_SECONDS = 60.0
"""How long Chromium may take to open its DevTools port on a loaded machine."""


def require_chromium() -> str:
    """Chromium's path; the test is skipped when it is missing, except in CI, where it must be there."""
    if os.path.exists(CHROMIUM):
        return CHROMIUM
    if os.environ.get("CI") == "true":
        pytest.fail(f"{CHROMIUM} is missing in CI: .ci/run installs Debian's chromium package")
    pytest.skip(f"{CHROMIUM} is not installed (apt-get install chromium)")


class Chromium:
    """A headless Chromium process with its own profile folder, ended by `close`."""

    def __init__(self, width: int = 1000, height: int = 640) -> None:
        self.profile = tempfile.mkdtemp(prefix="jointid-chromium-")
        self.process = subprocess.Popen(
            [require_chromium(), *FLAGS, f"--user-data-dir={self.profile}", f"--window-size={width},{height}",
             "about:blank"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        self.devtools_port = self._devtools_port()

    def _devtools_port(self) -> int:
        """Read `DevTools listening on ws://127.0.0.1:PORT/...` from Chromium's stderr."""
        deadline = time.monotonic() + START_SECONDS
        said = []
        for line in self.process.stderr:  # Chromium writes the line once the port is open
            said.append(line)
            found = re.search(r"DevTools listening on ws://[^:]+:(\d+)/", line)
            if found:
                return int(found.group(1))
            assert time.monotonic() < deadline, "Chromium did not open its DevTools port:\n" + "".join(said)
        raise AssertionError("Chromium ended before opening its DevTools port:\n" + "".join(said))

    async def page(self, http: aiohttp.ClientSession) -> Page:
        """The DevTools connection to the browser's open tab."""
        async with http.get(f"http://127.0.0.1:{self.devtools_port}/json") as response:
            targets = await response.json(content_type=None)
        target = next(target for target in targets if target["type"] == "page")
        page = Page(await http.ws_connect(target["webSocketDebuggerUrl"], max_msg_size=0))
        page.start()
        return page

    def close(self) -> None:
        """End the browser and remove its profile."""
        self.process.terminate()
        try:
            self.process.wait(30)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        self.process.stderr.close()
        shutil.rmtree(self.profile, ignore_errors=True)


class Page:
    """One tab's DevTools session: commands answered by id, events kept in order for `wait_for_event`."""

    def __init__(self, socket: aiohttp.ClientWebSocketResponse) -> None:
        self.socket = socket
        self.ids = itertools.count(1)
        self.pending: dict[int, asyncio.Future] = {}
        self.events: list[dict] = []
        self.new_event = asyncio.Event()
        self.reader: asyncio.Task | None = None

    def start(self) -> None:
        """Start reading the connection's messages."""
        self.reader = asyncio.create_task(self._read())

    async def _read(self) -> None:
        async for message in self.socket:
            data = json.loads(message.data)
            if "id" in data:
                future = self.pending.pop(data["id"], None)
                if future is not None and not future.done():
                    future.set_result(data)
            else:
                self.events.append(data)
                self.new_event.set()

    async def send(self, method: str, timeout: float = 60.0, **params) -> dict:
        """Run one DevTools command and return its result; AssertionError naming the method if it fails."""
        number = next(self.ids)
        future = asyncio.get_running_loop().create_future()
        self.pending[number] = future
        await self.socket.send_str(json.dumps({"id": number, "method": method, "params": params}))
        answer = await asyncio.wait_for(future, timeout)
        assert "error" not in answer, (method, answer["error"])
        return answer["result"]

    async def evaluate(self, expression: str, timeout: float = 60.0):
        """The value of a JavaScript expression in the page, promises awaited."""
        result = await self.send("Runtime.evaluate", timeout=timeout + 5, expression=expression,
                                 awaitPromise=True, returnByValue=True)
        assert "exceptionDetails" not in result, result["exceptionDetails"]
        return result["result"].get("value")

    async def wait_for_events(self, method: str, condition, count: int = 1, timeout: float = 60.0) -> list[dict]:
        """The first `count` events named `method` whose params satisfy `condition`, waiting for them."""
        deadline = time.monotonic() + timeout
        while True:
            found = [event for event in self.events if event["method"] == method and condition(event["params"])]
            if len(found) >= count:
                return found[:count]
            self.new_event.clear()
            left = deadline - time.monotonic()
            assert left > 0, f"waited for {count} {method} events; got {[e['method'] for e in self.events]}"
            try:
                await asyncio.wait_for(self.new_event.wait(), left)
            except TimeoutError:
                pass

    async def screenshot(self, path: Path) -> bytes:
        """Save a PNG screenshot of the page to `path` and return its bytes."""
        import base64

        data = base64.b64decode((await self.send("Page.captureScreenshot", format="png"))["data"])
        path.write_bytes(data)
        return data

    async def close(self) -> None:
        """Close the DevTools connection."""
        await self.socket.close()
        if self.reader is not None:
            await self.reader
