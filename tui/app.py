"""The jointid explorer: does the motion reveal the joint's parameters?"""

from __future__ import annotations

import gc
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Iterable

from textual import events
from textual.app import App, ComposeResult, SystemCommand
from textual.binding import Binding
from textual.content import Content
from textual.containers import Horizontal, Vertical
from textual.reactive import reactive, var
from textual.screen import Screen
from textual.widgets import Static

from jointid.derivatives import DEFAULT_ORDER, DEFAULT_WINDOW
from jointid.experiment import run_experiment
from jointid.fit import FitResult
from jointid.model import G, TRUE_PARAMETERS
from jointid.motions import TRAINING_MOTIONS
from jointid.report import readouts
from jointid.settings import DEFAULT_SETTINGS, SEED_LIMITS, Settings

from .charts import TorqueChart, heldout_chart, training_chart
from .commands import TourCommands
from .direct_controls import ActionButton, ChoiceList
from .fitting import FittingLine
from .footer import KeyFooter
from .log_mode import LogMode
from .precision import precision
from .readouts import ReadoutPanel
from .stepper import StepRange, Stepper
from . import third_party

if TYPE_CHECKING:  # the log reader is imported only when a log is opened
    from .log_source import LoadedLogs

NOISE_RANGE = StepRange("noise", 0.0, 1.0, 0.01, 0.1, decimals=2, unit="N m")
"""The explorer's noise control: 0.00 to 1.00 N m (the core allows more; `jointid fit` takes it)."""
SAMPLES_RANGE = StepRange("samples", 2, 240, 1, 10)
"""The explorer's sample-count control: 2 to 240."""
SEED_RANGE = StepRange("seed", SEED_LIMITS[0], SEED_LIMITS[1], 1, 100)
"""The explorer's seed control: the core's whole seed range."""
STEP_RANGES = (NOISE_RANGE, SAMPLES_RANGE, SEED_RANGE)
"""Every numeric control, in display order."""

FIELD_LABELS = {
    "noise": "Torque noise bound (N m)",
    "samples": "Training samples",
    "seed": "Seed",
}
"""Label shown beside each numeric control."""

STEPPER_HINT = "←/→ step, Shift+←/→ more, or type"
"""How to use a number field, shown under the fields."""

MIN_SIZE = (70, 22)
"""Smallest (width, height) the layout stays readable at; below it the screen asks for more."""
COMPACT_BELOW = (110, 32)
"""Narrower or shorter than this (width, height), readouts and known parameters use compact rows."""

STATUS_LINES = 4
"""Rows the status sentence always takes: most fits' sentences wrap to at most four lines,
at 80 columns as at 120, so a key press changes its text but not the screen's layout."""

FULL_COLLECTION_EVERY = 10_000
"""Young-generation collections between full garbage collections while keys keep coming
(Python's default is 10; a full collection takes 20 to 70 ms here, three key presses' worth):
in practice they run in pauses (`IDLE_COLLECTION_AFTER`); this only bounds endless typing."""
IDLE_COLLECTION_AFTER = 1.0
"""Seconds without a key press after which a pending full collection runs."""

MOTION_KEYS = {"1": ("rich", "Rich"), "2": ("slow", "Slow"), "3": ("holds", "Holds")}
"""Global keys that select a training motion, with the palette's short name."""
MOTION_GROUP = Binding.Group("Motion")
"""The motion keys share one footer entry."""


def size_classes(width: int, height: int) -> dict[str, bool]:
    """The screen's size classes: -narrow/-wide, -short/-tall, -compact when either is small, -too-small."""
    narrow, short = width < COMPACT_BELOW[0], height < COMPACT_BELOW[1]
    return {
        "-narrow": narrow, "-wide": not narrow, "-short": short, "-tall": not short,
        "-compact": narrow or short, "-too-small": width < MIN_SIZE[0] or height < MIN_SIZE[1],
    }


@lru_cache(maxsize=128)
def cached_experiment(settings: Settings) -> FitResult:
    """run_experiment, remembered: stepping back and forth repeats the same settings."""
    return run_experiment(settings)


def known_parameters_text(compact: bool = False) -> str:
    """The synthetic joint's true parameters and conventions, as shown beside the controls.

    Compact: two lines of at most 38 columns, which also give the units of the
    compact readout rows.
    """
    inertia, mass_moment, damping = (float(v) for v in TRUE_PARAMETERS)
    if compact:
        return (f"Known: I {inertia:g} kg m², h {mass_moment:g} kg m, g {G:g}\n"
                f"B {damping:g} N m s/rad; q from +x, ccw")
    return (
        f"Known joint: I = {inertia:g} kg m², h = {mass_moment:g} kg m, "
        f"B = {damping:g} N m s/rad, g = {G:g} m/s²; "
        "q from +x, counter-clockwise."
    )


class MainScreen(LogMode, Screen):
    """Controls, charts and readouts; the only place the four settings (and a loaded log) live."""

    BINDINGS = [
        *(
            # One footer entry, "1 2 3 Motion", so 80 columns have room for the views' keys.
            Binding(key, f"motion('{name}')", short, group=MOTION_GROUP,
                    tooltip=f"Train on {TRAINING_MOTIONS[name].label.lower()}")
            for key, (name, short) in MOTION_KEYS.items()
        ),
        # Priority, and not claimed by number fields, so these work while one has focus.
        Binding("r", "reset", "Reset", priority=True, tooltip="Restore the four default settings"),
        Binding("question_mark", "help", "Help", key_display="?", priority=True,
                tooltip="Keys, controls, model and things to try"),
        Binding("q", "quit", "Quit", priority=True, tooltip="Leave the explorer"),
        # The analysis views; s and m are not number characters, so they work in a number
        # field too, while e stays typeable there (1e-2), like the motion keys' digits.
        Binding("s", "sweep", "Sweep", priority=True,
                tooltip="Seed sweep: this experiment under many noise seeds"),
        Binding("m", "matrix", "Matrix", priority=True,
                tooltip="Cross-excitation: fit each motion, predict every motion"),
        Binding("e", "residuals", "Residuals", tooltip="Training residuals against t, q, qd, qdd"),
        # Joint logs (tui/log_mode.py). c is active only while a log is shown (check_action).
        Binding("ctrl+o", "open_log", "Open log", priority=True,
                tooltip="Load a CSV joint log as training or held-out data"),
        Binding("c", "close_log", "Close log",
                tooltip="Leave the log and return to the synthetic experiment"),
        Binding("ctrl+s", "export", "Export", priority=True,
                tooltip="Save the fit as JSON and the screen as SVG into a folder"),
    ]


    # var, not reactive: a reactive repaints its owner, here the whole screen (a full-screen
    # render, ~12 ms at 120x40, on every key press); the settings watcher refreshes exactly
    # the widgets whose content changed.
    motion: var[str] = var(DEFAULT_SETTINGS.motion, init=False)
    noise: var[float] = var(DEFAULT_SETTINGS.noise, init=False)
    samples: var[int] = var(DEFAULT_SETTINGS.samples, init=False)
    seed: var[int] = var(DEFAULT_SETTINGS.seed, init=False)
    settings: var[Settings] = var(DEFAULT_SETTINGS, init=False)
    """Derived from the four settings vars; its watcher is the one place results are computed.
    Read the current settings with `compute_settings()`: Textual calls a computed var's
    watcher on every read of it, which pushed the same fit to every view again."""
    logs: var[LoadedLogs | None] = var(None, init=False)
    """A loaded log and its fit; while set, it is shown instead of the settings' experiment."""

    def __init__(self, settings: Settings = DEFAULT_SETTINGS, logs: LoadedLogs | None = None) -> None:
        """Create the screen.

        Args:
            settings: Settings to open at.
            logs: A loaded log to show first (`jointid --csv`).
        """
        super().__init__()
        self._initial = settings
        self._initial_logs = logs
        self.result: FitResult | None = None

    def compose(self) -> ComposeResult:
        """Side panel with controls and readouts, chart column, too-small message, footer."""
        # Size classes before the children are styled, so the first resize restyles nothing.
        self.update_classes(size_classes(*self.app.size))
        compact = self.has_class("-compact")
        # A Static, not Textual's Header: one widget instead of four, the same line of text.
        yield Static(self.app.format_title(self.app.title, self.app.sub_title), id="title")
        with Horizontal(id="main"):
            with Vertical(id="side"):
                # No button starts pressed: the first settings push presses one, which
                # also moves the set's highlight to it.
                yield ChoiceList(
                    [*((f"motion-{name}", motion.label) for name, motion in TRAINING_MOTIONS.items()),
                     ("motion-log", "Log")],  # shown only while a log is
                    on_choose=self.choose_motion, hidden=("motion-log",), id="motion",
                )
                for steps in STEP_RANGES:
                    with Horizontal(classes="field"):
                        yield Static(FIELD_LABELS[steps.field], classes="field--label", markup=False)
                        yield Stepper(steps, getattr(self._initial, steps.field), id=steps.field)
                # After the fields, so Tab visits motion, noise, samples, seed, then Reset.
                with Horizontal(id="reset-row"):
                    yield ActionButton("Reset", on_press=self.action_reset, id="reset")
                    yield Static(STEPPER_HINT, id="stepper-hint", markup=False)
                yield Static("", id="log-note", markup=False)
                yield Static(known_parameters_text(compact), id="known", markup=False)
                yield ReadoutPanel(id="readouts", compact=compact)
            with Vertical(id="charts"):
                yield TorqueChart(id="training-chart")
                yield TorqueChart(id="heldout-chart")
        yield FittingLine(id="status", min_lines=STATUS_LINES)
        yield Static("", id="too-small", markup=False)
        yield KeyFooter()

    def on_mount(self) -> None:
        """Show the initial settings (set here so the single watcher does the first update)."""
        self.apply_settings(self._initial)
        if self._initial_logs is not None:
            self.logs = self._initial_logs

    def on_resize(self) -> None:
        """Compact rows on small terminals; a plain message when the terminal is too small to read."""
        width, height = self.size
        classes = size_classes(width, height)
        compact = classes["-compact"]
        switched = compact != self.has_class("-compact")
        if switched:
            self.query_one("#known", Static).update(known_parameters_text(compact))
            self.query_one(ReadoutPanel).set_compact(compact)
        self.update_classes(classes)  # restyles the screen only when a class changes
        if switched:
            self.show_log_note()  # reads the new -compact class
        if classes["-too-small"]:
            self.query_one("#too-small", Static).update(
                f"Please enlarge the terminal.\n\n"
                f"The jointid explorer needs at least {MIN_SIZE[0]} x {MIN_SIZE[1]} characters; "
                f"this one is {width} x {height}.\n\nPress q to quit."
            )

    def compute_settings(self) -> Settings:
        """The four reactives as one frozen Settings value."""
        return Settings(motion=self.motion, noise=self.noise, samples=self.samples, seed=self.seed)

    def watch_settings(self, settings: Settings) -> None:
        """Recompute the fit and push it down to every view (the one watcher)."""
        if self.logs is not None:  # the log is shown; the settings wait until it is closed
            return
        result = cached_experiment(settings)
        self.result = result
        self.query_one("#motion", ChoiceList).show_pressed(f"motion-{settings.motion}")
        for steps in STEP_RANGES:  # by id: a type query walks the whole screen (0.3 ms)
            self.query_one(f"#{steps.field}", Stepper).show_value(getattr(settings, steps.field))
        self.query_one("#training-chart", TorqueChart).show(training_chart(result))
        self.query_one("#heldout-chart", TorqueChart).show(heldout_chart(result))
        self.query_one(ReadoutPanel).show(readouts(result), precision(result))
        self.query_one("#status", FittingLine).show((Content(result.message),))

    def apply_settings(self, settings: Settings) -> None:
        """Set all four controls at once (reset, tour stops, start-up); leaves a log."""
        self.close_log()
        self.motion, self.noise = settings.motion, settings.noise
        self.samples, self.seed = settings.samples, settings.seed
        # Assigning equal values does not fire the computed watcher; force the first push.
        if self.result is None:
            self.watch_settings(self.compute_settings())

    def on_stepper_committed(self, message: Stepper.Committed) -> None:
        """A numeric control committed a value: store it in the matching reactive."""
        setattr(self, message.stepper.field, message.value)

    def choose_motion(self, button_id: str) -> None:
        """The motion list's choice (choosing the log's own entry changes nothing)."""
        if button_id != "motion-log":
            self.action_motion(button_id.removeprefix("motion-"))

    def action_motion(self, name: str) -> None:
        """Select a training motion (leaving a log)."""
        self.close_log()
        self.motion = name

    def action_reset(self) -> None:
        """Restore the four default settings."""
        self.apply_settings(DEFAULT_SETTINGS)

    def action_help(self) -> None:
        """Open the help screen."""
        from .help import HelpScreen  # Markdown is only needed when help is asked for

        self.app.push_screen(HelpScreen())

    # The views are imported when first opened, which keeps start-up fast.
    def action_sweep(self) -> None:
        """Open the seed-sweep view for the current settings."""
        if self.needs_synthetic("The seed sweep"):
            return
        from .sweep_screen import SweepScreen

        self.app.push_screen(SweepScreen(self.compute_settings()))

    def action_matrix(self) -> None:
        """Open the cross-excitation view for the current noise, samples and seed."""
        if self.needs_synthetic("The cross-excitation matrix"):
            return
        from .matrix_screen import MatrixScreen

        self.app.push_screen(MatrixScreen(self.compute_settings()))

    def action_residuals(self) -> None:
        """Open the residual view of the current fit."""
        from .residual_screen import ResidualScreen

        source = None if self.logs is None else f"log {self.logs.name}"
        self.app.push_screen(ResidualScreen(self.compute_settings(), self.result, source=source))

    async def action_quit(self) -> None:
        """Leave the explorer."""
        await self.app.action_quit()


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

    tune_gc = True
    """Whether a run tunes the garbage collector (`on_ready`); the key benchmark's --gc compares."""

    def on_load(self) -> None:
        """Turn on the third-party adapters the installed versions allow, before the first chart; log which."""
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
        self._idle_collection = self.set_interval(IDLE_COLLECTION_AFTER, self.collect_when_idle)

    def on_unmount(self) -> None:
        """Restore the collector's thresholds and unfreeze what `on_ready` froze (after a crash too)."""
        if getattr(self, "_gc_restore", None) is not None:
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
        # Bindings with a tooltip: the main screen's and the analysis views' (help has none).
        for binding in screen.BINDINGS:
            if isinstance(binding, Binding) and binding.tooltip:
                help_text = f"{binding.tooltip} (key {binding.key_display or binding.key})"
                yield SystemCommand(
                    binding.description, help_text,
                    lambda action=binding.action: screen.run_action(action),
                )

