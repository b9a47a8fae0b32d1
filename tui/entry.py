"""The terminal UI's one entry point: `jointid` (no subcommand) calls `explore` through an entry point."""

from __future__ import annotations

from typing import TYPE_CHECKING

from jointid.derivatives import DEFAULT_ORDER, DEFAULT_WINDOW
from jointid.settings import Settings

from .controls import check_explorer_settings

if TYPE_CHECKING:
    from jointid.logfit import LoadedLogs


def explore(settings: Settings, logs: LoadedLogs | None = None,
            derivatives: tuple[int, int] = (DEFAULT_WINDOW, DEFAULT_ORDER)) -> int:
    """Run the explorer until the user quits and return the exit status.

    Args:
        settings: Settings to open at; SettingsError if outside the explorer's ranges.
        logs: A loaded log to open on (`jointid --csv`).
        derivatives: Savitzky-Golay window and order for logs opened later with Ctrl+O.
    """
    check_explorer_settings(settings)
    from .app import JointIdApp  # after the check: a refused value costs no Textual import

    app = JointIdApp(settings, logs, derivatives=derivatives)
    app.restore_gc = False  # the process ends with the app: see JointIdApp.restore_gc
    app.run()
    return app.return_code or 0
