"""The jointid explorer app: does the motion reveal the joint's parameters?"""

from __future__ import annotations

import gc
import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Iterable

from textual.actions import parse as parse_action
from textual.app import App, SystemCommand
from textual.binding import Binding
from textual.screen import Screen

from jointid.options import DEFAULT_ORDER, DEFAULT_WINDOW
from jointid.synthetic.settings import DEFAULT_SETTINGS, Settings

from .notices import NEWS_SECONDS, ROUTINE_SECONDS
from .palette import TourCommands
from .screens.main import MainScreen
from .third_party import adapter as third_party

if TYPE_CHECKING:  # the log reader and its low-pass are imported only when a log is opened
    from jointid.estimation.low_pass import FilterRequest
    from jointid.logs.conventions import LogConventions
    from jointid.studies.log_fit import LoadedLogs


class NoTerminal(Exception):
    """The explorer was started where it can neither read keys nor draw (str() is the one line why)."""


def terminal_problem() -> str | None:
    """Why Textual's terminal driver cannot run here, or None: it reads keys from stdin and draws on stderr.

    Without a terminal on both, Textual starts anyway and waits for keys that never come (`jointid < /dev/null`
    ran for ever). A driver chosen through TEXTUAL_DRIVER (textual-serve's web driver) brings its own input and
    output and is not checked.
    """
    if os.environ.get("TEXTUAL_DRIVER"):
        return None
    for stream, name in ((sys.__stdin__, "standard input"), (sys.__stderr__, "standard error (where it draws)")):
        if stream is None or not stream.isatty():
            return (f"the explorer needs a terminal, and its {name} is not one; run `jointid` in a terminal, "
                    "or use a subcommand such as `jointid fit`")
    return None


def action_works(screen: Screen, action: str) -> bool:
    """Whether a screen's binding action would run now (its check_action says yes, not off or hidden)."""
    _, name, parameters = parse_action(action)
    return bool(screen.check_action(name, parameters))


class JointIdApp(App):
    """The jointid terminal explorer."""

    CSS_PATH = Path(__file__).with_name("app.tcss")  # absolute, so subclasses elsewhere find it
    TITLE = "jointid"
    SUB_TITLE = "Does the motion reveal the parameters?"
    COMMANDS = App.COMMANDS | {TourCommands}

    def __init__(self, settings: Settings = DEFAULT_SETTINGS, logs: LoadedLogs | None = None,
                 derivatives: tuple[int | None, int] = (DEFAULT_WINDOW, DEFAULT_ORDER),
                 filtering: FilterRequest | None = None, conventions: LogConventions | None = None) -> None:
        """Create the app.

        Args:
            settings: Settings to open at.
            logs: A loaded log to open on (`jointid --csv`).
            derivatives: Savitzky-Golay window and order for logs without qd or qdd,
                those opened later too (`jointid --window --order`); a window of None is automatic.
            filtering: The parallel low-pass for logs opened later (`jointid --cutoff --decimate`);
                None is automatic, as `FilterRequest()`.
            conventions: The column map and angle convention for logs opened later (`jointid --columns
                --zero --clockwise`), so a held-out log is read as the training log was; None is jointid's own.
        """
        super().__init__()
        self.initial_settings = settings
        self.initial_logs = logs
        self.derivatives = derivatives
        self.filtering = filtering
        self.conventions = conventions

    def notify(self, message: str, *, title: str = "", severity="information", timeout: float | None = None,
               markup: bool = True) -> None:
        """Textual's `App.notify`, with a warning's default timeout short (tui/notices.py)."""
        if timeout is None:
            timeout = ROUTINE_SECONDS if severity == "warning" else NEWS_SECONDS
        super().notify(message, title=title, severity=severity, timeout=timeout, markup=markup)

    def on_notify(self, event) -> None:
        """Take down the notifications of the new one's title before Textual shows it: one box per kind, so three
        refused values are one box, not three stacked over the charts."""
        third_party.forget_notifications(self, event.notification.title)

    def run(self, *, headless: bool = False, **kwargs):
        """Textual's `App.run`; in a terminal's place, refused with NoTerminal before anything is drawn."""
        if not headless:
            problem = terminal_problem()
            if problem is not None:
                raise NoTerminal(problem)
        return super().run(headless=headless, **kwargs)

    def get_default_screen(self) -> Screen:
        """The main screen at the initial settings."""
        return MainScreen(self.initial_settings, self.initial_logs)

    tune_gc = True
    """Whether a run freezes the heap its start built (`on_ready`); the key benchmark's --gc compares."""
    restore_gc = True
    """Whether the run's end gives the collector back as it was. `jointid` (tui/entry.py) turns it off: its
    process ends with the app, and unfreezing first makes that exit walk the whole heap; not doing so buys
    0.10 of the explorer's start to the process's end (bench_startup_budget no-gc-restore-at-exit)."""

    def on_load(self) -> None:
        """Pause the garbage collector until the first frame; turn on the third-party adapters the installed
        versions allow, before the first chart; log which.

        Start-up builds tens of thousands of objects that live as long as the app (the screen's widgets,
        their styles, the fit, the figures): the collections Python runs while they are built free little
        and walk them all. Pausing them buys 0.04 to 0.05 of the explorer's start (bench_startup_budget
        gc-paused-to-first-frame): under the budget's 5 %, kept for the explorer's 1.10x start-up limit
        (benchmarks/README.md, "Start-up budget"). `on_ready` resumes collecting.
        """
        if self.tune_gc and gc.isenabled():
            gc.disable()
            self._gc_paused = True
        for line in third_party.activate():
            self.log(f"third-party adapter: {line}")

    def on_ready(self) -> None:
        """Exempt everything built so far from garbage collection scans, for this run only.

        Textual, numpy and plotext leave a large heap of objects that live as long as the app; frozen, no
        collection walks them again, nor does the process's exit: that buys 0.10 of the explorer's start to
        the process's end (bench_startup_budget gc-frozen-at-first-frame). `on_unmount` unfreezes, so a test
        or a program embedding the app gets its collector back as it was. Objects someone else froze are
        left alone.
        """
        if not self.tune_gc:
            return
        self._gc_unfreeze = gc.get_freeze_count() == 0
        if self._gc_unfreeze:
            gc.freeze()
        self.resume_gc()

    def resume_gc(self) -> None:
        """Turn the collector back on if `on_load` paused it (once the first frame is up, or the run ends)."""
        if getattr(self, "_gc_paused", False):
            self._gc_paused = False
            gc.enable()

    def on_unmount(self) -> None:
        """Unfreeze what `on_ready` froze (after a crash too)."""
        self.resume_gc()  # a crash before the first frame leaves it paused
        if self.restore_gc and getattr(self, "_gc_unfreeze", False):
            self._gc_unfreeze = False
            gc.unfreeze()

    def get_system_commands(self, screen: Screen) -> Iterable[SystemCommand]:
        """Textual's commands plus every key binding with a tooltip, so nothing needs a key."""
        yield from super().get_system_commands(screen)
        # Bindings with a tooltip: the main screen's and the analysis views' (help has none),
        # those that work now (Close log only with a log shown, the sweep only without).
        for binding in screen.BINDINGS:
            if isinstance(binding, Binding) and binding.tooltip and action_works(screen, binding.action):
                help_text = f"{binding.tooltip} (key {binding.key_display or binding.key})"
                yield SystemCommand(
                    binding.description, help_text,
                    lambda action=binding.action: screen.run_action(action),
                )

