"""`jointid serve`: the explorer in a browser, one explorer process per browser tab (textual-serve, `jointid[web]`).

It takes the explorer's own flags (`jointid serve --noise 0.2` opens every tab
where `jointid --noise 0.2` opens) and the server's: where it listens, how many
sessions it runs at once, when an idle one ends, and the one folder that Ctrl+O
may read in the browser. Every session runs `python -m jointid` with the
explorer's flags under Textual's web driver; the app sees `App.is_web` and
delivers its exports as downloads (tui/web.py).
"""

from __future__ import annotations

import argparse
import errno
import os
import sys

from ..memory import available_memory
from ..text_safety import shown_name
from .arguments import (
    OneLineParser,
    UserError,
    add_model_argument,
    add_settings_arguments,
    positive_number,
    whole_number,
)
from .commands import SUBCOMMANDS
from .exit_status import ExitStatus
from .log_arguments import add_log_arguments

NAME = "serve"

DEFAULT_HOST = "127.0.0.1"
"""Only this machine, unless --host says otherwise: a class's server is opened on purpose."""
DEFAULT_PORT = 8000
DEFAULT_IDLE_TIMEOUT = 30 * 60
"""Seconds without a key after which a session ends: a lesson's pause, not a tab left open all day."""

SESSION_MEMORY_MIB = 110
"""Resident memory of one session's explorer process once its student has opened every analysis view (107 MiB
measured; 57 MiB after the lesson's keys alone), rounded up: bench_serve.py, benchmarks/README.md."""
MEMORY_SHARE = 0.75
"""Share of the memory available at start that the sessions may take by default; the rest is the system's."""
SESSIONS_PER_CORE = 10
"""Sessions a core serves by default: 20 sessions pressing a key a second answered within 2x of one alone on a
2-core machine (p95 key to frame; bench_serve.py, benchmarks/README.md), more were not measured."""

DATA_ENVIRONMENT = "JOINTID_WEB_DATA"
"""Environment variable through which a session learns the --data folder (tui/web.py reads it)."""

SERVER_PID_ENVIRONMENT = "JOINTID_SERVER_PID"
"""Environment variable telling a session's explorer its server's process id, so it ends with the server
(tui/web.py)."""

SERVER_FLAGS = ("host", "port", "public_url", "allow_origin", "max_sessions", "idle_timeout", "data")
"""The flags that are the server's own; every other flag after `serve` is the explorer's, passed to each session."""


def public_url(text: str) -> str:
    """--public-url: an http or https address with a host (no query or fragment), without its final slash."""
    from urllib.parse import urlsplit

    try:
        parts = urlsplit(text)
        parts.port  # noqa: B018 - raises ValueError for a port that is not a number from 0 to 65535
    except ValueError:
        parts = None
    if (parts is None or parts.scheme.lower() not in ("http", "https") or not parts.hostname or parts.query
            or parts.fragment or not text.isprintable() or " " in text):
        raise argparse.ArgumentTypeError(f"{shown_name(text)!r} is not an http:// or https:// address with a host, "
                                         "e.g. https://jointid.example.org")
    return text.rstrip("/")  # paths are added to it


def web_origin(text: str) -> str:
    """--allow-origin: a site as browsers name it, scheme://host[:port] (a final slash allowed, no path)."""
    from urllib.parse import urlsplit

    url = public_url(text)
    if urlsplit(url).path:
        raise argparse.ArgumentTypeError(f"{shown_name(text)!r} has a path; give the site alone, e.g. "
                                         "https://jointid.example.org")
    return url


def add_server_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the server's own flags (SERVER_FLAGS)."""
    group = parser.add_argument_group("the server")
    group.add_argument("--host", default=DEFAULT_HOST,
                       help=f"address to listen on; default {DEFAULT_HOST} (this machine only); 0.0.0.0 for every "
                       "network interface")
    group.add_argument("--port", type=whole_number(1, 65535), default=DEFAULT_PORT,
                       help=f"TCP port to listen on; default {DEFAULT_PORT}")
    group.add_argument("--public-url", metavar="URL", default=None, type=public_url,
                       help="the address browsers use, when it is not http://HOST:PORT, e.g. "
                       "https://jointid.example.org behind a reverse proxy (https makes the page use wss); "
                       "pages from it may use the server")
    group.add_argument("--allow-origin", metavar="URL", action="append", type=web_origin, default=[],
                       help="also let pages from this site (scheme://host[:port]) use the server; may be given "
                       "more than once. Pages of any other site are refused (403), so that a page a student "
                       "visits cannot drive a session")
    group.add_argument("--max-sessions", type=whole_number(1, 100_000), default=None, metavar="N",
                       help="most sessions (browser tabs) at once; one more is told the server is full; "
                       f"default: what {MEMORY_SHARE * 100:.0f}%% of the memory available at start holds at "  # %% for argparse
                       f"{SESSION_MEMORY_MIB} MiB a session (printed at start)")
    group.add_argument("--idle-timeout", type=positive_number, default=DEFAULT_IDLE_TIMEOUT, metavar="SECONDS",
                       help=f"end a session after this many seconds without a key; default {DEFAULT_IDLE_TIMEOUT} "
                       "(30 minutes)")
    group.add_argument("--data", metavar="DIR", default=None,
                       help="the folder whose logs Ctrl+O may open in the browser (nothing outside it, symlinks "
                       "included); without it Ctrl+O is off in the browser")


def add_parser(subparsers) -> None:
    """Attach the `serve` subcommand: the explorer's flags and the server's."""
    parser = subparsers.add_parser(
        NAME,
        help=SUBCOMMANDS[NAME].summary,
        description="Serve the explorer to web browsers (textual-serve): each browser tab gets its own "
        "explorer, opened as `jointid` would be with the same flags. In a browser Ctrl+S downloads the "
        "JSON and the SVG, and Ctrl+O opens logs from the --data folder only.",
    )
    add_server_arguments(parser)
    add_settings_arguments(parser)
    add_model_argument(parser)
    add_log_arguments(parser)


def explorer_words(argv: list[str]) -> list[str]:
    """The explorer's flags among the words after `serve` (the server's own left out), as typed."""
    server_only = OneLineParser(prog="jointid serve", add_help=False)
    add_server_arguments(server_only)
    _, words = server_only.parse_known_args(argv)
    return words


def session_command(words: list[str]) -> list[str]:
    """What each session runs: this Python's `jointid` with the explorer's flags."""
    return [sys.executable, "-m", "jointid", *words]


def check_explorer_flags(words: list[str]) -> None:
    """Refuse, before any browser connects, the explorer flags `jointid` itself would refuse (a bad log too)."""
    from . import parse
    from .explorer_command import CHECK_ENTRY_POINT_NAME, load_explorer
    from .explorer_command import run as run_explorer

    check_settings = load_explorer(CHECK_ENTRY_POINT_NAME)  # the explorer's ranges, narrower than `fit`'s

    def explore(settings, *args, **kwargs) -> int:
        check_settings(settings)  # a SettingsError becomes run_explorer's one line, as `jointid` itself gives
        return ExitStatus.SUCCESS

    run_explorer(parse(words), explore=explore)


def data_folder(path: str | None) -> str | None:
    """The --data folder, absolute with its links resolved; UserError (one line) when it is not a folder."""
    if path is None:
        return None
    from ..files import shown_path

    if not os.path.isdir(path):
        problem = "not a folder" if os.path.lexists(path) else "no such folder"
        raise UserError(f"--data {shown_path(path)}: {problem}")
    return os.path.realpath(path)


def default_max_sessions(memory: int, cores: int = 1) -> int:
    """The fewer of the sessions MEMORY_SHARE of `memory` bytes holds at SESSION_MEMORY_MIB each and
    SESSIONS_PER_CORE for each of `cores` (at least 1)."""
    by_memory = int(memory * MEMORY_SHARE / (SESSION_MEMORY_MIB * 2**20))
    return max(1, min(by_memory, SESSIONS_PER_CORE * cores))


def sessions_sentence(max_sessions: int | None, memory: int, cores: int | None = None) -> tuple[int, str]:
    """The session limit and the line the server prints about it at start."""
    if max_sessions is not None:
        return max_sessions, f"At most {max_sessions} sessions at once (--max-sessions)."
    cores = cores or os.cpu_count() or 1
    limit = default_max_sessions(memory, cores)
    by_memory = int(memory * MEMORY_SHARE / (SESSION_MEMORY_MIB * 2**20))
    return limit, (f"At most {limit} sessions at once: the fewer of {by_memory} ({MEMORY_SHARE:.0%} of the "
                   f"{memory / 2**30:.1f} GiB of memory available now, at about {SESSION_MEMORY_MIB} MiB a session) "
                   f"and {SESSIONS_PER_CORE * cores} ({SESSIONS_PER_CORE} for each of {cores} cores, as measured); "
                   "--max-sessions to change.")


def check_port_free(host: str, port: int) -> None:
    """UserError (one line) if nothing can listen on host:port (in use, or an address this machine lacks)."""
    import socket  # here: its import alone cost `jointid serve --help` 2 ms, 0.1 of its start

    try:
        addresses = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)
    except socket.gaierror as error:
        raise UserError(f"--host {host}: {error.strerror}") from None
    family, kind, protocol, _, address = addresses[0]
    with socket.socket(family, kind, protocol) as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # as aiohttp's own listener does
        try:
            probe.bind(address)
        except OSError as error:
            if error.errno == errno.EADDRINUSE:
                raise UserError(f"--port {port}: the port is in use on {host}; choose another with --port") \
                    from None
            raise UserError(f"cannot listen on {host}:{port}: {error.strerror or error}") from None


def load_web_server():
    """The web server module; UserError naming the extra when textual-serve is not installed."""
    try:
        from . import web_server
    except ImportError:
        raise UserError("jointid serve needs textual-serve: pip install 'jointid[web]'") from None
    return web_server


def run(args: argparse.Namespace) -> int:
    """Check every flag, then serve the explorer until Ctrl+C; exit status 0."""
    typed = args.argv
    if typed[:1] != [NAME]:
        raise UserError("put the explorer's flags after `serve` (jointid serve --noise 0.2 ...)")
    words = explorer_words(typed[1:])
    check_explorer_flags(words)
    data = data_folder(args.data)
    web_server = load_web_server()
    check_port_free(args.host, args.port)
    max_sessions, sentence = sessions_sentence(args.max_sessions, available_memory())
    server = web_server.JointIdServer(
        session_command(words), host=args.host, port=args.port,
        public_url=args.public_url, allowed_origins=tuple(args.allow_origin),
        max_sessions=max_sessions, idle_timeout=args.idle_timeout,
        environment={DATA_ENVIRONMENT: data or "", SERVER_PID_ENVIRONMENT: str(os.getpid())}, announcement=sentence,
    )
    try:
        server.serve()
    except OSError as error:  # the port taken between the check and the start
        raise UserError(f"cannot listen on {args.host}:{args.port}: {error.strerror or error}") from None
    return ExitStatus.SUCCESS
