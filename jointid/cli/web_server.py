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
  quit a few seconds after its browser went;
- a request from a page of another site (its `Origin`) is refused with 403, so
  a page a student visits cannot drive a session (cross-site WebSocket
  hijacking); only this server's own address, `--public-url` and
  `--allow-origin` are trusted;
- open connections are bounded and an unfinished request ends after
  UNFINISHED_TIMEOUT seconds, so a flood of idle sockets is shed instead of
  using up the open files and locking browsers out;
- a browser's frame that is not textual-serve's envelope is ignored, and a
  download's file name is quoted as RFC 6266 says.

Each session's start and end is logged with its process id on standard output.
"""

from __future__ import annotations

import asyncio
import ipaddress
import json
import logging
import signal
import time
import uuid
from pathlib import Path
from urllib.parse import quote, urlsplit

from aiohttp import WSMsgType, web
from textual_serve.app_service import AppService
from textual_serve.server import Server

from ..text_safety import shown_name

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

MAX_FRAME_BYTES = 1 << 20
"""Largest browser frame taken (a pasted text); a larger one closes its own connection only (code 1009)."""

UNFINISHED_TIMEOUT = 10.0
"""Seconds a connection may stay idle or keep a request unfinished before it is closed (aiohttp's 75 s let
idle sockets hold every open file)."""

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


def origin_of(url: str) -> str | None:
    """The origin (scheme://host[:port], lower case, default port left out) of an http(s) URL; None if it has
    none (not http or https, no host, or a port that is not a number)."""
    try:
        parts = urlsplit(url.strip())
        port = parts.port
    except ValueError:
        return None
    if parts.scheme.lower() not in ("http", "https") or not parts.hostname:
        return None
    host = parts.hostname.lower()
    if ":" in host:
        host = f"[{host}]"  # an IPv6 address, bracketed as in a URL
    default = {"http": 80, "https": 443}[parts.scheme.lower()]
    return f"{parts.scheme.lower()}://{host}" + ("" if port in (None, default) else f":{port}")


def _ip_address(host: str):
    """`host` as an IP address, or None when it is a name."""
    try:
        return ipaddress.ip_address(host.strip("[]"))
    except ValueError:
        return None


def origin_allowed(origin: str | None, host_header: str | None, trusted: frozenset[str], port: int) -> bool:
    """Whether a request whose page came from `origin` may use the server.

    Browsers send Origin with every WebSocket and every cross-site fetch, so a request without it is not a page's
    (a script, curl) and passes. A page's is allowed when its origin is trusted (this server's address,
    --public-url, --allow-origin), is this machine under another loopback name at this server's port
    (localhost for 127.0.0.1), or is the address the request itself was sent to, given as an IP address (a
    name could be pointed anywhere by its DNS, so only a trusted name counts).
    """
    if origin is None:
        return True
    normal = origin_of(origin)
    if normal is None:
        return False  # "null" (a sandboxed frame, a file:// page) or garbage
    if normal in trusted:
        return True
    parts = urlsplit(normal)
    origin_port = parts.port or {"http": 80, "https": 443}[parts.scheme]
    address = _ip_address(parts.hostname)
    if (parts.hostname == "localhost" or (address is not None and address.is_loopback)) and origin_port == port:
        return True
    return address is not None and host_header is not None and normal.split("://", 1)[1] == host_header.lower()


def parse_envelope(text: str) -> tuple[str, object] | None:
    """A browser frame's (kind, data) when it is textual-serve's `["kind", data]` envelope with data of the kind's
    type; None for anything else (not JSON, NaN or Infinity, not a list, a kind that is not a word, a key text
    that is not Unicode, a size that is not a whole number), which the caller ignores."""
    def refuse_constant(name: str):
        raise ValueError(name)

    try:
        envelope = json.loads(text, parse_constant=refuse_constant)
    except (ValueError, RecursionError):
        return None
    if not isinstance(envelope, list) or not envelope or not isinstance(envelope[0], str):
        return None
    kind, data = (envelope + [None])[:2]
    if kind == "stdin":
        if not isinstance(data, str):
            return None
        try:
            data.encode("utf-8")
        except UnicodeEncodeError:  # a lone surrogate: no key sends one
            return None
    elif kind == "resize":
        if not isinstance(data, dict) or not all(isinstance(data.get(side), int) and not isinstance(
                data.get(side), bool) for side in ("width", "height")):
            return None
    return kind, data


def download_name(name: str) -> str:
    """A file name from a session made safe to save: no folder separators, no control or other unprintable
    character (each becomes `_`), no leading dot; 'download' if nothing is left."""
    safe = "".join(character if character.isprintable() and character not in "/\\" else "_" for character in name)
    return safe.strip(" .") or "download"


def content_disposition(kind: str, name: str) -> str:
    """A Content-Disposition header for `name` (RFC 6266): an ASCII `filename` in quotes for old browsers and the
    exact name, percent-encoded, as `filename*` (RFC 5987), which every current browser prefers."""
    name = download_name(name)
    # The fallback keeps only characters no parser of the header can misread (naive ones split at every `;`).
    ascii_name = "".join(character if character.isascii() and (character.isalnum() or character in " ._-+,()[]")
                         else "_" for character in name)
    return f"{kind}; filename=\"{ascii_name}\"; filename*=UTF-8''{quote(name, safe='')}"


def raise_open_file_limit(wanted: int) -> int:
    """Raise this process's soft limit of open files towards `wanted` (never above the hard limit); the limit
    now in force."""
    try:
        import resource  # POSIX only
    except ImportError:
        return wanted
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft != resource.RLIM_INFINITY and soft < wanted:
        new = wanted if hard == resource.RLIM_INFINITY else min(wanted, hard)
        try:
            resource.setrlimit(resource.RLIMIT_NOFILE, (new, hard))
            soft = new
        except (ValueError, OSError):
            pass  # keep what we have; the connection limit below is fitted to it
    return soft if soft != resource.RLIM_INFINITY else wanted


FILES_PER_SESSION = 4
"""Open files one session costs the server besides its connections: its explorer's three pipes and a spare."""
SPARE_FILES = 64
"""Open files kept for the server itself (its listener, logs, Python's own)."""


def connection_limit(max_sessions: int, open_files: int) -> int:
    """How many connections to keep open at most: room for each session's WebSocket, a page load and a download,
    plus spare, but never more than the open files leave after the sessions' own (yet always room for every
    session's WebSocket and 16 more)."""
    wanted = 4 * max_sessions + SPARE_FILES
    return max(max_sessions + 16, min(wanted, open_files - FILES_PER_SESSION * max_sessions - SPARE_FILES))


class BoundedSite(web.BaseSite):
    """A TCP listener that keeps at most `limit` connections: a new one beyond it closes the oldest connection
    that holds no request (an idle or half-sent one), or itself when every connection is busy."""

    def __init__(self, runner: web.AppRunner, host: str, port: int, limit: int, busy: set) -> None:
        super().__init__(runner)
        self.host, self.port, self.limit, self.busy = host, port, limit, busy
        self.shed = 0
        """Connections closed to make room, for the log."""

    @property
    def name(self) -> str:
        """The address, as aiohttp's sites name themselves."""
        return f"http://{self.host}:{self.port}"

    async def start(self) -> None:
        """Listen, handing every new connection to aiohttp's handler through `_admit`."""
        await super().start()
        self._server = await asyncio.get_running_loop().create_server(self._admit, self.host, self.port)

    def _admit(self):
        """aiohttp's handler for a new connection, after room is made for it."""
        server = self._runner.server
        handler = server()
        connections = server.connections
        if len(connections) >= self.limit:
            idle = next((connection for connection in connections if connection not in self.busy), None)
            if idle is None:
                asyncio.get_running_loop().call_soon(handler.force_close)  # every place is in use: not this one
            else:
                idle.force_close()
            self.shed += 1
            if self.shed in (1, 100) or self.shed % 1000 == 0:
                log.info("connections at the limit of %d: %d closed to make room", self.limit, self.shed)
        return handler


class JointIdServer(Server):
    """textual-serve's Server with at most `max_sessions` sessions and an idle timeout of `idle_timeout` seconds."""

    def __init__(self, argv: list[str], *, host: str, port: int, public_url: str | None, max_sessions: int,
                 idle_timeout: float, environment: dict[str, str], announcement: str = "",
                 allowed_origins: tuple[str, ...] = ()) -> None:
        super().__init__(" ".join(argv), host=host, port=port, title="jointid", public_url=public_url,
                         templates_path=PAGE_FOLDER)
        self.argv = argv
        self.max_sessions = max_sessions
        self.idle_timeout = idle_timeout
        self.environment = environment
        self.announcement = announcement
        self.sessions: dict[Session, web.WebSocketResponse] = {}
        """Every running session and its browser's connection."""
        self.trusted_origins = frozenset(filter(None, map(origin_of, (self.public_url, *allowed_origins))))
        """Origins whose pages may use the server besides its own loopback and IP addresses (origin_allowed)."""
        self.busy: set = set()
        """The connections with a request under way (a page, a download, a session's WebSocket)."""
        self.stopping: asyncio.Event | None = None

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
        """textual-serve's `serve` on a listener that bounds connections, announcing the address once the port is
        open; until SIGINT or SIGTERM."""
        self.debug = debug
        self.initialize_logging()
        asyncio.run(self._serve())

    def request_exit(self) -> None:
        """Stop serving (SIGINT, SIGTERM)."""
        if self.stopping is not None:
            self.stopping.set()

    async def make_app(self) -> web.Application:
        """textual-serve's application (its page, /ws, /download, /static) behind `_guard`."""
        app = await self._make_app()
        app.middlewares.append(self._guard)
        return app

    async def _serve(self) -> None:
        """Listen until asked to stop, then close every session (on_shutdown) and the listener."""
        self.stopping = asyncio.Event()
        loop = asyncio.get_running_loop()
        loop.add_signal_handler(signal.SIGINT, self.request_exit)
        loop.add_signal_handler(signal.SIGTERM, self.request_exit)
        app = await self.make_app()
        runner = web.AppRunner(app, handle_signals=False, keepalive_timeout=UNFINISHED_TIMEOUT)
        await runner.setup()
        open_files = raise_open_file_limit(FILES_PER_SESSION * self.max_sessions + 4 * self.max_sessions
                                           + 2 * SPARE_FILES)
        try:
            await BoundedSite(runner, self.host, self.port, connection_limit(self.max_sessions, open_files),
                              self.busy).start()
            self.announce()
            await self.stopping.wait()
        finally:
            await runner.cleanup()

    @web.middleware
    async def _guard(self, request: web.Request, handler) -> web.StreamResponse:
        """Refuse a page of another site (403, nothing started); mark the connection busy while it is served."""
        origin = request.headers.get("Origin")
        if not origin_allowed(origin, request.host, self.trusted_origins, self.port):
            log.info("refused %s from origin %s (not this server's; --allow-origin to trust it)",
                     shown_name(request.path), shown_name(origin))
            return web.Response(status=403, text="jointid serve: pages of other sites may not use this server; "
                                "its own page, --public-url and --allow-origin may.\n")
        self.busy.add(request.protocol)
        try:
            return await handler(request)
        finally:
            self.busy.discard(request.protocol)

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

    async def handle_download(self, request: web.Request) -> web.StreamResponse:
        """textual-serve's download, its file name quoted (content_disposition): a name holding `;`, quotes or
        CR LF is saved under its own name, never read as other header fields."""
        key = request.match_info["key"]
        try:
            download = await self.download_manager.get_download_metadata(key)
        except KeyError:
            raise web.HTTPNotFound(text="No such download: it was fetched already, or its session ended.") \
                from None
        response = web.StreamResponse()
        response.headers["Content-Type"] = download.mime_type + (
            f"; charset={download.encoding}" if download.encoding else "")
        kind = "inline" if download.open_method == "browser" else "attachment"
        response.headers["Content-Disposition"] = content_disposition(kind, download.file_name)
        await response.prepare(request)
        async for chunk in self.download_manager.download(key):
            await response.write(chunk)
        await response.write_eof()
        return response

    async def handle_websocket(self, request: web.Request) -> web.WebSocketResponse:
        """Start a session for this connection, or tell it the server is full; end the session when it goes."""
        websocket = web.WebSocketResponse(heartbeat=15, max_msg_size=MAX_FRAME_BYTES)
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
        """textual-serve's message loop, noting when the person last typed or resized; a frame that is not a
        well-formed envelope is ignored (parse_envelope)."""
        async for message in websocket:
            if message.type != WSMsgType.TEXT:
                continue
            envelope = parse_envelope(message.data)
            if envelope is None:
                continue
            kind, data = envelope
            if kind in ACTIVITY:
                app_service.last_activity = time.monotonic()
            if kind == "stdin":
                await app_service.send_bytes(data.encode("utf-8"))
            elif kind == "resize":
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
    except (TypeError, ValueError, OverflowError):  # OverflowError: infinity
        return default
    return number if 1 <= number <= 1000 else default

