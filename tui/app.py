"""The jointid explorer app: does the motion reveal the joint's parameters?"""

from __future__ import annotations

import gc
from pathlib import Path
from typing import TYPE_CHECKING, Iterable

from textual import events
from textual.app import App, SystemCommand
from textual.binding import Binding
from textual.screen import Screen

from jointid.derivatives import DEFAULT_ORDER, DEFAULT_WINDOW
from jointid.settings import DEFAULT_SETTINGS, Settings

from .commands import TourCommands
from .main_screen import MainScreen

if TYPE_CHECKING:  # the log reader is imported only when a log is opened
    from jointid.logfit import LoadedLogs

FULL_COLLECTION_EVERY = 10_000
"""Young-generation collections between full garbage collections while keys keep coming
(Python's default is 10; a full collection takes 20 to 70 ms here, three key presses' worth):
in practice they run in pauses (`IDLE_COLLECTION_AFTER`); this only bounds endless typing."""
IDLE_COLLECTION_AFTER = 1.0
"""Seconds without a key press after which a pending full collection runs."""


class JointIdApp(App):
    """The jointid terminal explorer."""

    CSS_PATH = Path(__file__).with_name("app.tcss")  # absolute, so subclasses elsewhere find it
    TITLE = "jointid"
    SUB_TITLE = "Does the motion reveal the parameters?"
    COMMANDS = App.COMMANDS | {TourCommands}

    def __init__(self, settings: Settings = DEFAULT_SETTINGS, logs: LoadedLogs | None = None,
                 derivatives: tuple[int, int] = (DEFAULT_WINDOW, DEFAULT_ORDER)) -> None:
        """Create the app.

        Args:
            settings: Settings to open at.
            logs: A loaded log to open on (`jointid --csv`).
            derivatives: Savitzky-Golay window and order for logs without qd or qdd,
                those opened later too (`jointid --window --order`).
        """
        super().__init__()
        self.initial_settings = settings
        self.initial_logs = logs
        self.derivatives = derivatives

    def get_default_screen(self) -> Screen:
        """The main screen at the initial settings."""
        return MainScreen(self.initial_settings, self.initial_logs)

    def on_ready(self) -> None:
        """Exempt everything built so far from garbage collection scans.

        Textual, numpy and plotext leave a large heap of objects that live as
        long as the app; every full collection walked all of them, 30 to 90 ms,
        a few times a minute while keys were pressed. Frozen, they are skipped.
        What the app builds later (cached figures and fits, Textual's caches)
        still made each full collection cost 20 to 70 ms, one in ten key presses:
        full collections wait for a pause in the typing instead (`collect_when_idle`).
        """
        gc.freeze()
        young, middle, _ = gc.get_threshold()
        gc.set_threshold(young, middle, FULL_COLLECTION_EVERY)
        self._idle_collection = self.set_interval(IDLE_COLLECTION_AFTER, self.collect_when_idle)

    def on_event(self, event: events.Event):
        """Every key press postpones the idle-time garbage collection."""
        if isinstance(event, events.Key) and hasattr(self, "_idle_collection"):
            self._idle_collection.reset()
        return super().on_event(event)

    def collect_when_idle(self) -> None:
        """Run the full garbage collection Python would have run by now, while no key is pressed."""
        if gc.get_count()[2] >= gc.get_threshold()[1]:  # as many young collections as its default
            gc.collect()

    def get_system_commands(self, screen: Screen) -> Iterable[SystemCommand]:
        """Textual's commands plus every key binding with a tooltip, so nothing needs a key."""
        yield from super().get_system_commands(screen)
        # Bindings with a tooltip: the main screen's and the analysis views' (help has none).
        for binding in screen.BINDINGS:
            if isinstance(binding, Binding) and binding.tooltip:
                help_text = f"{binding.tooltip} (key {binding.key_display or binding.key})"
                yield SystemCommand(
                    binding.description, help_text,
                    lambda action=binding.action: screen.run_action(action),
                )

