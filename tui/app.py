"""The jointid explorer app: does the motion reveal the joint's parameters?"""

from __future__ import annotations

import gc
from pathlib import Path
from typing import TYPE_CHECKING, Iterable

from textual import events
from textual.actions import parse as parse_action
from textual.app import App, SystemCommand
from textual.binding import Binding
from textual.screen import Screen

from jointid.options import DEFAULT_ORDER, DEFAULT_WINDOW
from jointid.synthetic.settings import DEFAULT_SETTINGS, Settings

from .palette import TourCommands
from .screens.main import MainScreen
from .third_party import adapter as third_party

if TYPE_CHECKING:  # the log reader and its low-pass are imported only when a log is opened
    from jointid.estimation.low_pass import FilterRequest
    from jointid.logs.conventions import LogConventions
    from jointid.studies.log_fit import LoadedLogs

FULL_COLLECTION_EVERY = 10_000
"""Young-generation collections between full garbage collections while keys keep coming
(Python's default is 10; a full collection takes 20 to 70 ms here, three key presses' worth):
in practice they run in pauses (`IDLE_COLLECTION_AFTER`); this only bounds endless typing."""
IDLE_COLLECTION_AFTER = 1.0
"""Seconds without a key press after which a pending full collection runs."""


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

    def get_default_screen(self) -> Screen:
        """The main screen at the initial settings."""
        return MainScreen(self.initial_settings, self.initial_logs)

    tune_gc = True
    """Whether a run tunes the garbage collector (`on_ready`); the key benchmark's --gc compares."""
    restore_gc = True
    """Whether the run's end gives the collector back as it was. `jointid` (tui/entry.py) turns it off: its
    process ends with the app, and unfreezing first made that exit walk the whole heap, about 0.1 s
    (benchmarks/bench_tui_startup.py measures start-up to the process's end)."""

    def on_load(self) -> None:
        """Pause the garbage collector until the first frame; turn on the third-party adapters the installed
        versions allow, before the first chart; log which.

        Start-up builds tens of thousands of objects that live as long as the app (the screen's widgets,
        their styles, the fit, the figures): the collections Python runs while they are built free
        little and walk them all, about a fifth of the time from here to the first frame (perf_counter
        marks, 2026-11-23). `on_ready` freezes what start-up built and resumes collecting; the few
        thousand objects of start-up garbage are frozen with it, the price of skipping those walks.
        """
        if self.tune_gc and gc.isenabled():
            gc.disable()
            self._gc_paused = True
        for line in third_party.activate():
            self.log(f"third-party adapter: {line}")

    def on_ready(self) -> None:
        """Exempt everything built so far from garbage collection scans, for this run only.

        Textual, numpy and plotext leave a large heap of objects that live as
        long as the app; every full collection walked all of them, 30 to 90 ms,
        a few times a minute while keys were pressed. Frozen, they are skipped.
        What the app builds later (cached figures and fits, Textual's caches)
        still made each full collection cost 20 to 70 ms, one in ten key presses:
        full collections wait for a pause in the typing instead (`collect_when_idle`).
        `on_unmount` undoes both, so a test or a program embedding the app gets
        its collector back as it was. Objects someone else froze are left alone.

        Measured 2026-11-23, `benchmarks/bench_tui_keys.py --gc both --runs 4`
        (runs alternating, 720 timed presses each way at 120x40): Python's stock
        collector against this tuning, min 8.4 vs 8.4 ms (ratio 1.00), median
        15.5 vs 14.9 ms (1.04), p95 37.8 vs 25.1 ms (1.51), max 122.5 vs 40.3 ms
        (3.04); 46 presses against 9 took over two frames (33 ms). The typical
        press is no faster; the tuning removes the long pauses, so it stays.
        """
        if not self.tune_gc:
            return
        self._gc_restore = gc.get_threshold()
        young, middle, _ = self._gc_restore
        self._gc_unfreeze = gc.get_freeze_count() == 0
        if self._gc_unfreeze:
            gc.freeze()
        gc.set_threshold(young, middle, FULL_COLLECTION_EVERY)
        self.resume_gc()
        self._idle_collection = self.set_interval(IDLE_COLLECTION_AFTER, self.collect_when_idle)

    def resume_gc(self) -> None:
        """Turn the collector back on if `on_load` paused it (once the first frame is up, or the run ends)."""
        if getattr(self, "_gc_paused", False):
            self._gc_paused = False
            gc.enable()

    def on_unmount(self) -> None:
        """Restore the collector's thresholds and unfreeze what `on_ready` froze (after a crash too)."""
        self.resume_gc()  # a crash before the first frame leaves it paused
        if self.restore_gc and getattr(self, "_gc_restore", None) is not None:
            gc.set_threshold(*self._gc_restore)
            self._gc_restore = None
            if self._gc_unfreeze:
                gc.unfreeze()

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
        # Bindings with a tooltip: the main screen's and the analysis views' (help has none),
        # those that work now (Close log only with a log shown, the sweep only without).
        for binding in screen.BINDINGS:
            if isinstance(binding, Binding) and binding.tooltip and action_works(screen, binding.action):
                help_text = f"{binding.tooltip} (key {binding.key_display or binding.key})"
                yield SystemCommand(
                    binding.description, help_text,
                    lambda action=binding.action: screen.run_action(action),
                )

