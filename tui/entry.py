"""The terminal UI's one entry point: `jointid` (no subcommand) calls `explore` through an entry point."""

from __future__ import annotations

from typing import TYPE_CHECKING

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
    from .app import JointIdApp  # after the check: a refused value costs no Textual import

    app = JointIdApp(settings, logs, derivatives=derivatives, filtering=filtering, conventions=conventions)
    app.restore_gc = False  # the process ends with the app: see JointIdApp.restore_gc
    app.run()  # Textual restores the terminal before it returns, and prints a crash's traceback
    return exit_status(app)


def exit_status(app) -> int:
    """The process exit status for a finished app: 1 if it ended by an exception, else its return code.

    Textual sets the return code to 1 when a handler raises, but any `exit()` that
    runs later while the app shuts down (a screen's cleanup, a quit already queued)
    sets it back to 0; the exception it keeps is the reliable sign of a crash.
    """
    if third_party.app_exception(app) is not None:
        return ExitStatus.ERROR
    return app.return_code or ExitStatus.SUCCESS
