"""The terminal UI's one entry point: `jointid` (no subcommand) calls `explore` through an entry point."""

from __future__ import annotations

import asyncio
import signal
import threading
from contextlib import contextmanager
from typing import TYPE_CHECKING

from jointid.cli.arguments import UserError
from jointid.cli.exit_status import ExitStatus
from jointid.options import DEFAULT_ORDER, DEFAULT_WINDOW
from jointid.synthetic.settings import Settings

from .ranges import check_explorer_settings
from .third_party import adapter as third_party

if TYPE_CHECKING:
    from jointid.estimation.low_pass import FilterRequest
    from jointid.logs.conventions import LogConventions
    from jointid.studies.log_fit import LoadedLogs


def explore(settings: Settings, logs: LoadedLogs | None = None,
            derivatives: tuple[int | None, int] = (DEFAULT_WINDOW, DEFAULT_ORDER),
            filtering: FilterRequest | None = None, conventions: LogConventions | None = None) -> int:
    """Run the explorer until the user quits and return the exit status.

    Args:
        settings: Settings to open at; SettingsError if outside the explorer's ranges.
        logs: A loaded log to open on (`jointid --csv`).
        derivatives: Savitzky-Golay window (None: automatic) and order for logs opened later with Ctrl+O.
        filtering: The parallel low-pass for those logs (`--cutoff`, `--decimate`); None is automatic.
        conventions: The column map and angle convention for those logs (`--columns`, `--zero`,
            `--clockwise`); None is jointid's own.
    """
    check_explorer_settings(settings)
    # Imported after the check: a refused value costs no Textual import.
    from .app import JointIdApp, NoTerminal

    app = JointIdApp(settings, logs, derivatives=derivatives, filtering=filtering, conventions=conventions)
    app.restore_gc = False  # the process ends with the app: see JointIdApp.restore_gc
    interrupt = Interrupt(app)
    from .web import start_session

    start_session()  # a session of `jointid serve` only: ends with its server, reads only in --data
    try:
        with interrupt.handling():
            app.run()  # Textual restores the terminal before it returns, and prints a crash's traceback
    except NoTerminal as error:
        raise UserError(str(error)) from None
    return exit_status(app, interrupted=interrupt.received)


class Interrupt:
    """SIGINT (`kill -INT`; the terminal's Ctrl+C is a key to Textual) closes the explorer as `q` does, status 130.

    Python's own handler would raise KeyboardInterrupt inside whichever task runs, and asyncio's cancels the
    app's task, which Textual takes as an ordinary exit: status 0, as if the user had quit.
    """

    def __init__(self, app) -> None:
        self.app = app
        self.received = False

    @contextmanager
    def handling(self):
        """Handle SIGINT while the block runs (only the main thread may; elsewhere Python's handler stays)."""
        if threading.current_thread() is not threading.main_thread():
            yield
            return
        previous = signal.signal(signal.SIGINT, self)
        try:
            yield
        finally:
            signal.signal(signal.SIGINT, previous)

    def __call__(self, signum, frame) -> None:
        self.received = True
        try:
            loop = asyncio.get_running_loop()  # the app's, when the signal arrives while it runs
        except RuntimeError:
            raise KeyboardInterrupt from None  # before the app started or after it ended: stop as Python would
        loop.call_soon_threadsafe(self.app.exit, None, ExitStatus.INTERRUPTED)


def exit_status(app, interrupted: bool = False) -> int:
    """The process exit status for a finished app: 1 if it ended by an exception, 130 if by SIGINT, else its
    return code.

    Textual sets the return code to 1 when a handler raises, but any `exit()` that
    runs later while the app shuts down (a screen's cleanup, a quit already queued)
    sets it back to 0; the exception it keeps is the reliable sign of a crash, and
    the handler's own flag that of an interrupt.
    """
    if third_party.app_exception(app) is not None:
        return ExitStatus.ERROR
    if interrupted:
        return ExitStatus.INTERRUPTED
    return app.return_code or ExitStatus.SUCCESS
