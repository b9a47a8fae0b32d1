"""Open a local page in Debian's headless Chromium, record every request the page makes, and take a screenshot.

Chromium is driven over the DevTools protocol on a pipe (`--remote-debugging-pipe`: it reads commands from file
descriptor 3 and writes replies and events to 4, each a JSON message ended by a NUL byte), so no port is opened
and no driver library is needed. The page's own requests are the Network domain's `requestWillBeSent` events for
its target, which sees every fetch the page makes (documents, images, style sheets, fonts, scripts), whatever the
scheme, and nothing of the browser's own background traffic; DNS is mapped to nothing besides, so a request that
slipped through would fail rather than leave the machine.
"""

from __future__ import annotations

import base64
import json
import os
import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

CHROMIUM = Path("/usr/bin/chromium")
"""Debian's package; .ci/run installs it."""

FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run", "--no-default-browser-check",
         "--disable-extensions", "--mute-audio", "--host-resolver-rules=MAP * ~NOTFOUND",
         "--remote-debugging-pipe")
"""A quiet browser: no background fetches, no first-run pages, no name resolution, DevTools on the pipe."""

TIMEOUT = 60.0
"""Seconds to wait for any one reply or event before giving up (a loaded CI machine starts Chromium slowly)."""


@dataclass(frozen=True)
class PageVisit:
    """What happened when a page was opened: every URL it requested (its own first) and a PNG screenshot."""

    requests: tuple[str, ...]
    screenshot: bytes


class DevTools:
    """A DevTools protocol session with a Chromium process over its pipe."""

    def __init__(self, process: subprocess.Popen, commands: int, replies: int):
        self.process, self.commands, self.replies = process, commands, replies
        self.buffer = b""
        self.next_id = 0
        self.events: list[dict] = []

    def send(self, method: str, session: str | None = None, **params) -> dict:
        """Send one command and return its result (events that arrive meanwhile are kept in `events`)."""
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params}
        if session is not None:
            message["sessionId"] = session
        os.write(self.commands, json.dumps(message).encode() + b"\0")
        while True:
            reply = self.receive()
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply["result"]
            self.events.append(reply)

    def receive(self) -> dict:
        """The next message from Chromium."""
        deadline = time.monotonic() + TIMEOUT
        while b"\0" not in self.buffer:
            if time.monotonic() > deadline or self.process.poll() is not None:
                raise RuntimeError("Chromium did not answer")
            chunk = os.read(self.replies, 1 << 16)
            if not chunk:
                raise RuntimeError("Chromium closed its pipe")
            self.buffer += chunk
        message, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(message)

    def wait_for(self, method: str) -> dict:
        """The first event named `method` (kept or still to come)."""
        for index, event in enumerate(self.events):
            if event.get("method") == method:
                return self.events.pop(index)
        while True:
            event = self.receive()
            if event.get("method") == method:
                return event
            self.events.append(event)


def visit(pages: list[Path], *, dark: bool = False, size: tuple[int, int] = (1200, 2000)) -> list[PageVisit]:
    """Open each of `pages` (local files) in turn in one headless Chromium at `size`, in the light or dark colour
    scheme, and return the requests each made and a screenshot of its whole length."""
    profile = tempfile.mkdtemp(prefix="jointid-chromium-")
    to_chromium, commands = os.pipe()
    replies, from_chromium = os.pipe()
    process = None
    try:
        # Chromium's ends of the pipes must be its descriptors 3 and 4: bash moves them there (dash takes only one
        # digit), then is replaced by Chromium.
        process = subprocess.Popen(
            ["/bin/bash", "-c", f'exec "$0" "$@" 3<&{to_chromium} 4>&{from_chromium}', str(CHROMIUM), *FLAGS,
             f"--user-data-dir={profile}", f"--window-size={size[0]},{size[1]}", "about:blank"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            pass_fds=(to_chromium, from_chromium))
        os.close(to_chromium)
        os.close(from_chromium)
        tools = DevTools(process, commands, replies)
        target = tools.send("Target.createTarget", url="about:blank")["targetId"]
        session = tools.send("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
        tools.send("Network.enable", session)
        tools.send("Page.enable", session)
        tools.send("Emulation.setEmulatedMedia", session,
                   features=[{"name": "prefers-color-scheme", "value": "dark" if dark else "light"}])
        visits = []
        for page in pages:
            tools.events.clear()
            tools.send("Page.navigate", session, url=page.resolve().as_uri())
            tools.wait_for("Page.loadEventFired")
            height = tools.send("Page.getLayoutMetrics", session)["cssContentSize"]["height"]
            shot = tools.send("Page.captureScreenshot", session, format="png", captureBeyondViewport=True,
                              clip={"x": 0, "y": 0, "width": size[0], "height": min(height, 16000), "scale": 1})
            requests = tuple(event["params"]["request"]["url"] for event in tools.events
                             if event.get("method") == "Network.requestWillBeSent")
            visits.append(PageVisit(requests, base64.b64decode(shot["data"])))
        tools.send("Browser.close")
        return visits
    finally:
        if process is not None:
            try:
                process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
        for descriptor in (commands, replies):
            try:
                os.close(descriptor)
            except OSError:
                pass
        shutil.rmtree(profile, ignore_errors=True)
