"""`jointid serve`'s web server: textual-serve's, with a bound on sessions, an idle timeout and sure process ends.

textual-serve (the `jointid[web]` extra) gives every WebSocket connection its own
explorer process, driven through Textual's web driver, and turns the app's
`deliver_text`/`deliver_binary` into browser downloads. What a class needs on
top, added here by subclassing its Server and AppService:

- at most `max_sessions` processes: a page load or a connection beyond them gets
  a message saying the server is full, and the sessions running keep going;
- a session without a key or a resize for `idle_timeout` seconds is ended, so a
  tab left open does not hold a place all day;
- a session's process is started without a shell (textual-serve runs `sh -c`,
  which keeps the shell between it and the app) and is killed if it has not
  quit a few seconds after its browser went.

Each session's start and end is logged with its process id on standard output.
"""

from __future__ import annotations

import asyncio
import logging
import signal
import time
import uuid
from pathlib import Path

from aiohttp import WSMsgType, web
from textual_serve.app_service import AppService
from textual_serve.server import Server

log = logging.getLogger("textual-serve")

PAGE_FOLDER = Path(__file__).with_name("web_page")
"""textual-serve's page with downloads as links (pop-up blockers allow two) and the close reason shown."""

QUIT_GRACE_SECONDS = 5.0
"""How long a session's process has to quit after its browser went before it is killed."""

FULL_CLOSE_CODE = 1013
"""WebSocket close code 'try again later' (RFC 6455's registry), for a connection beyond the limit."""

IDLE_CLOSE_CODE = 1001
"""WebSocket close code 'going away', for a session ended for want of keys."""

CLIENT_COOKIE = "jointid_client"
"""A random name per browser, set with the page: a reverse proxy in front of several servers hashes it so that a
tab's WebSocket and its downloads reach the same server (README.md, "Serve")."""

ACTIVITY = {"stdin", "resize"}
"""Browser messages that show a person is there; the page's own pings and focus changes do not."""


def full_message(max_sessions: int) -> str:
    """What a browser beyond the limit is told (a WebSocket close reason: at most 123 bytes)."""
    return f"jointid serve is full: all {max_sessions} sessions are in use. Try again in a few minutes."


def idle_message(idle_timeout: float) -> str:
    """What a session ended for want of keys is told."""
    return f"Session ended after {idle_timeout:g} s without a key. Reload the page to start again."


STOPPED_MESSAGE = "The jointid server stopped."
"""What every browser is told when the server stops."""

FULL_PAGE = """<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>jointid: server full</title></head>
<body style="background:#0c181f;color:#f0f0f0;font-family:sans-serif;padding:3em">
<p>{message}</p><p><button type="button" onclick="location.reload()">Try again</button></p>
</body></html>
"""


class Session(AppService):
    """One browser's explorer process, started without a shell and sure to end when the browser goes."""

    def __init__(self, argv: list[str], environment: dict[str, str], **kwargs) -> None:
        super().__init__(" ".join(argv), **kwargs)
        self.argv = argv
        self.extra_environment = environment
        self.last_activity = time.monotonic()

    def _build_environment(self, width: int = 80, height: int = 24) -> dict[str, str]:
        """textual-serve's environment (the web driver, the size) plus jointid's for web mode (the --data folder)."""
        return super()._build_environment(width, height) | self.extra_environment

    async def _open_app_process(self, width: int = 80, height: int = 24) -> asyncio.subprocess.Process:
        """Start the explorer itself, not a shell around it, so that its process id is the one to end."""
        self._process = process = await asyncio.create_subprocess_exec(
            *self.argv,
            stdin=asyncio.subprocess.PIPE,
            stdout=asyncio.subprocess.PIPE,
            stderr=asyncio.subprocess.PIPE,
            env=self._build_environment(width=width, height=height),
        )
        self._stdin = process.stdin
        return process

    async def run(self) -> None:
        """textual-serve's reading of the app's output; then the browser's connection is closed, also when the
        process ended without saying so (a crash, a flag the explorer refused), so the page says the session ended."""
        await super().run()
        await self.remote_close()

    @property
    def pid(self) -> int | None:
        """The explorer process's id, once started."""
        return None if self._process is None else self._process.pid

    async def stop(self) -> None:
        """Ask the app to quit as textual-serve does; kill its process if it has not ended QUIT_GRACE_SECONDS later."""
        process = self._process
        if process is None:
            return
        try:
            await asyncio.wait_for(super().stop(), QUIT_GRACE_SECONDS)
            await asyncio.wait_for(process.wait(), QUIT_GRACE_SECONDS)
        except (TimeoutError, OSError):
            if process.returncode is None:
                process.kill()
        await process.wait()


class JointIdServer(Server):
    """textual-serve's Server with at most `max_sessions` sessions and an idle timeout of `idle_timeout` seconds."""

    def __init__(self, argv: list[str], *, host: str, port: int, public_url: str | None, max_sessions: int,
                 idle_timeout: float, environment: dict[str, str], announcement: str = "") -> None:
        super().__init__(" ".join(argv), host=host, port=port, title="jointid", public_url=public_url,
                         templates_path=PAGE_FOLDER)
        self.argv = argv
        self.max_sessions = max_sessions
        self.idle_timeout = idle_timeout
        self.environment = environment
        self.announcement = announcement
        self.sessions: dict[Session, web.WebSocketResponse] = {}
        """Every running session and its browser's connection."""

    @property
    def full(self) -> bool:
        """Whether every allowed session is taken."""
        return len(self.sessions) >= self.max_sessions

    def initialize_logging(self) -> None:
        """Plain lines on standard output (textual-serve's rich handler draws boxes and colours)."""
        logging.basicConfig(level=logging.DEBUG if self.debug else logging.INFO, format="%(message)s")
        logging.getLogger("aiohttp.access").setLevel(logging.WARNING)

    async def on_startup(self, app: web.Application) -> None:
        """Nothing: textual-serve prints its logo here, before it listens; `announce` speaks once it does."""

    async def on_shutdown(self, app: web.Application) -> None:
        """Close every browser's connection as the server stops, so each session ends at once (aiohttp would
        otherwise wait for the connections to end by themselves)."""
        await asyncio.gather(*(websocket.close(code=IDLE_CLOSE_CODE, message=STOPPED_MESSAGE.encode())
                               for websocket in list(self.sessions.values())), return_exceptions=True)

    def announce(self, *_) -> None:
        """Say where the explorer is served and how many sessions it takes, once the server listens."""
        print(f"jointid serve: the explorer at {self.public_url}", flush=True)
        if self.announcement:
            print(self.announcement, flush=True)
        print("Press Ctrl+C to stop.", flush=True)

    def serve(self, debug: bool = False) -> None:
        """textual-serve's `serve`, announcing the address once the port is open rather than before."""
        self.debug = debug
        self.initialize_logging()
        loop = asyncio.new_event_loop()
        loop.add_signal_handler(signal.SIGINT, self.request_exit)
        loop.add_signal_handler(signal.SIGTERM, self.request_exit)
        web.run_app(self._make_app(), host=self.host, port=self.port, handle_signals=False, loop=loop,
                    print=self.announce)

    async def handle_index(self, request: web.Request) -> web.StreamResponse:
        """The page, or a page saying the server is full (status 503) when every session is taken; either gives
        the browser a random CLIENT_COOKIE if it has none."""
        if self.full:
            response = web.Response(status=503, content_type="text/html",
                                    text=FULL_PAGE.format(message=full_message(self.max_sessions)))
        else:
            response = await super().handle_index(request)
        if CLIENT_COOKIE not in request.cookies:
            response.set_cookie(CLIENT_COOKIE, uuid.uuid4().hex, httponly=True, samesite="Strict")
        return response

    async def handle_websocket(self, request: web.Request) -> web.WebSocketResponse:
        """Start a session for this connection, or tell it the server is full; end the session when it goes."""
        websocket = web.WebSocketResponse(heartbeat=15)
        await websocket.prepare(request)
        if self.full:
            message = full_message(self.max_sessions)
            await websocket.send_bytes(f"\x1b[2J\x1b[H{message}\r\n".encode())
            await websocket.close(code=FULL_CLOSE_CODE, message=message.encode())
            log.info("refused a session: %d of %d in use", len(self.sessions), self.max_sessions)
            return websocket
        width = _whole(request.query.get("width"), 80)
        height = _whole(request.query.get("height"), 24)
        session = Session(self.argv, self.environment, write_bytes=websocket.send_bytes,
                          write_str=websocket.send_str, close=websocket.close,
                          download_manager=self.download_manager, debug=self.debug)
        self.sessions[session] = websocket
        watchdog = None
        try:
            await session.start(width, height)
            log.info("session started: pid %d (%d of %d)", session.pid, len(self.sessions), self.max_sessions)
            watchdog = asyncio.create_task(self._end_when_idle(websocket, session))
            await self._process_messages(websocket, session)
        except asyncio.CancelledError:
            await websocket.close()
        except Exception:  # one browser's failure must not stop the others' server
            log.exception("session failed")
        finally:
            if watchdog is not None:
                watchdog.cancel()
            await session.stop()
            self.sessions.pop(session, None)
            if session.pid is not None:
                log.info("session ended: pid %d (%d of %d)", session.pid, len(self.sessions), self.max_sessions)
        return websocket

    async def _process_messages(self, websocket: web.WebSocketResponse, app_service: Session) -> None:
        """textual-serve's message loop, noting when the person last typed or resized."""
        async for message in websocket:
            if message.type != WSMsgType.TEXT:
                continue
            try:
                kind, data = (message.json() + [None])[:2]
            except (ValueError, TypeError):
                continue  # not textual-serve's ["kind", data] envelope
            if kind in ACTIVITY:
                app_service.last_activity = time.monotonic()
            if kind == "stdin" and isinstance(data, str):
                await app_service.send_bytes(data.encode("utf-8"))
            elif kind == "resize" and isinstance(data, dict):
                await app_service.set_terminal_size(_whole(data.get("width"), 80), _whole(data.get("height"), 24))
            elif kind == "ping":
                await websocket.send_json(["pong", data])
            elif kind == "blur":
                await app_service.blur()
            elif kind == "focus":
                await app_service.focus()

    async def _end_when_idle(self, websocket: web.WebSocketResponse, session: Session) -> None:
        """Close the connection (ending its session) once it has gone `idle_timeout` seconds without activity."""
        while True:
            left = session.last_activity + self.idle_timeout - time.monotonic()
            if left <= 0:
                log.info("session idle for %g s: ending pid %d", self.idle_timeout, session.pid)
                await websocket.close(code=IDLE_CLOSE_CODE, message=idle_message(self.idle_timeout).encode())
                return
            await asyncio.sleep(left)


def _whole(value, default: int) -> int:
    """A terminal dimension from the browser: a whole number from 1 to 1000, else `default`."""
    try:
        number = int(value)
    except (TypeError, ValueError):
        return default
    return number if 1 <= number <= 1000 else default

