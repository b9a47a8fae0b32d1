"""The explorer's main screen: controls, charts and readouts of one source of data.

The screen holds the only state: the synthetic experiment's settings and, when
one is loaded, a log. Whichever is shown is the *source*; `show_source` is the
one path that fits it (or takes the log's fit) and pushes the result down to
every widget. Widgets never hold a setting of their own: they display what the
screen shows them and report the user's choices through their callbacks.
"""

from __future__ import annotations

import os
from dataclasses import replace
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

from textual import work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical
from textual.content import Content
from textual.events import ScreenResume
from textual.screen import Screen
from textual.widgets import Static

from jointid.estimation.fit import FitResult
from jointid.model.terms import PLAIN, G
from jointid.model.truth import LESSON_JOINT, TrueJoint
from jointid.options import default_log_model
from jointid.present.charts import heldout_chart, log_training_chart, training_chart
from jointid.present.readouts import precision, readouts
from jointid.present.status import (
    compact_status,
    log_sources,
    log_status,
    status_message,
)
from jointid.present.text import format_number
from jointid.studies.experiment import run_experiment
from jointid.synthetic.motions import TRAINING_MOTIONS
from jointid.text_safety import shown_name
from jointid.synthetic.settings import DEFAULT_SETTINGS, Settings

from ..ranges import FIELD_LABELS, STEP_RANGES
from ..sizes import MIN_SIZE, size_classes
from ..widgets.charts import TorqueChart
from ..widgets.direct_controls import ActionButton, ChoiceList
from ..widgets.fitting import FittingLine
from ..widgets.footer import KeyFooter
from ..widgets.readouts import ReadoutPanel
from ..widgets.stepper import Stepper

# The log reader, file dialog, progress dialog, export and views are imported when first used:
# the first frame needs none of them, which buys 0.15 of the explorer's start (bench_startup_budget lazy-ui-modules).
if TYPE_CHECKING:
    from jointid.model.terms import JointModel
    from jointid.studies.log_fit import LoadedLogs, LoadRequest
    from jointid.studies.runs import PooledRuns

    from .loading import LoadingScreen

STEPPER_HINT = "←/→ step, Shift+←/→ more, or type"
"""How to use a number field, shown under the fields."""

FROM_LOG = "from log"
"""Text of the noise, samples and seed fields while a log is shown."""
LOG_NOTE = "From log: c or 1/2/3 for synthetic"
GAINS_LOG_NOTE = "From log: c or 1/2/3; g: gains"
"""A voltage log's note names the gains view, which the footer has no room for; as short, so it takes no row more."""
"""The first line of the note shown while a log is (the help gives the rest)."""


STATUS_LINES = 4
"""Rows the status sentence always takes: most fits' sentences wrap to at most four lines,
at 80 columns as at 120, so a key press changes its text but not the screen's layout."""

COMPACT_EXTENDED_STATUS_LINES = 3
"""Rows the status takes on compact screens under a model with more terms than the lesson's: its shorter
sentence fits three, and the side panel needs the fourth for the fifth parameter (80x24)."""

MOTION_KEYS = {"1": ("rich", "Rich"), "2": ("slow", "Slow"), "3": ("holds", "Holds")}
"""Global keys that select a training motion, with the palette's short name."""
DESIGNED = "design"
"""The motion list's fourth motion: the one the design view made (key 4, once there is one)."""
MOTION_GROUP = Binding.Group("Motion")
"""The motion keys share one footer entry."""
VIEWS_GROUP = Binding.Group("Views")
"""The analysis views' keys: an entry each where the footer has room, one shared entry at 80 columns."""


@lru_cache(maxsize=128)
def cached_experiment(settings: Settings) -> FitResult:
    """run_experiment, remembered: stepping back and forth repeats the same settings."""
    return run_experiment(settings)


def report_page(runs, logs, result, settings, drive=None) -> str:
    """The HTML report of what the explorer shows: several runs, a log (with the gains of a voltage log, and of a
    torque log when the session has a motor `drive`), or the synthetic experiment's fit."""
    from jointid.present import report
    from jointid.present.report_writers import html_page, made_by

    if runs is not None:
        page = report.runs_report(runs, extras=gains_texts(runs, drive))
    elif logs is not None:
        page = report.logs_report(logs, extras=gains_texts(logs, drive))
    else:
        page = report.synthetic_report(result, settings)
    return html_page(report.draw(page), made_by("the explorer (Ctrl+R)"))


def gains_sections(fit, drive) -> list[tuple[str, ...]]:
    """The parts of the gains a log's fit (or several runs pooled) gives, and of the physical parameters behind a
    voltage fit's gains through the session's motor `drive`: what the gains view and the report show. GainsError
    when the fit gives none (a torque log without a motor, no unique fit)."""
    from jointid.present.gains import gains_parts, motor_parts
    from jointid.studies.gains import arm_gains, motor_parameters

    sections = [gains_parts(arm_gains(fit, drive))]
    if drive is not None and not (fit.runs[0] if hasattr(fit, "runs") else fit).result.model.effort.is_torque:
        sections.append(motor_parts(motor_parameters(fit, drive)))
    return sections


def gains_texts(fit, drive) -> tuple[str, ...]:
    """gains_sections as the report's texts (`jointid report --gains wpilib` and its motor's); none when the fit
    gives no gains."""
    from jointid.studies.gains import GainsError

    try:
        return tuple("\n".join(part for part in section if part) for section in gains_sections(fit, drive))
    except GainsError:  # a torque log without a motor, or no unique fit: the report's tables say so
        return ()


def known_parameters_text(joint: TrueJoint = LESSON_JOINT, compact: bool = False) -> str:
    """The synthetic joint's true parameters and conventions, as shown beside the controls.

    Compact: two lines of at most 38 columns, which also give the units of the
    compact readout rows (missing physics in place of the conventions).
    """
    values = dict(zip(PLAIN.names, joint.values_for(PLAIN)))
    unit = {parameter.name: parameter.unit for parameter in PLAIN.parameters}
    extras = [f"{name} {value:g} {PHYSICS_UNITS[name]}" for name, value in missing_physics(joint)]
    if compact:  # the missing physics take the conventions' place: 80x24 has two rows for this
        return (f"Known: I {values['I']:g} {unit['I']}, h {values['h']:g} {unit['h']}, g {G:g}\n"
                f"B {values['B']:g} {unit['B']}; " + (", ".join(extras) if extras else "q from +x, ccw"))
    known = ", ".join(f"{name} = {values[name]:g} {unit[name]}" for name in PLAIN.names)
    text = f"Known joint: {known}, g = {G:g} m/s²; q from +x, counter-clockwise."
    return text + (f" It also has {', '.join(extras)}." if extras else "")


PHYSICS_UNITS = {"Fc": "N m", "tau0": "N m", "q0": "rad"}
"""Units of the missing physics, by the symbol the model ladder gives it."""


def missing_physics(joint: TrueJoint) -> list[tuple[str, float]]:
    """(symbol, value) of each effect beyond the plain model that the joint has."""
    return [(name, value) for name, value in (("Fc", joint.coulomb), ("tau0", joint.bias), ("q0", joint.angle_offset))
            if value]


def log_note(logs: LoadedLogs) -> str:
    """Why the synthetic controls are gone and how to get them back, then one short line per log read.

    The number fields and Reset give way while a log is shown, which leaves rows here for the files read:
    the status sentence then need not name them.
    """
    training, *others = log_sources(logs)
    first = LOG_NOTE if logs.result.model.effort.is_torque else GAINS_LOG_NOTE
    return "\n".join((first, f"{training}; {logs.result.training.count} fitted", *others))


def runs_note(runs, shown: int) -> str:
    """Which of several runs is shown and where they are pooled: 'Run 2 of 3 · u: every run, pooled I 0.1872'."""
    pooled = ", ".join(f"{name} {format_number(runs.params[name], 4)}" for name in runs.shared[:2])
    return f"Run {shown + 1} of {len(runs.runs)} · u: every run, pooled {pooled}"


class MainScreen(Screen):
    """Controls, charts and readouts; the only place the settings (and a loaded log) live."""

    BINDINGS = [
        *(
            # One footer entry, "1 2 3 Motion", so 80 columns have room for the views' keys.
            Binding(key, f"motion('{name}')", short, group=MOTION_GROUP,
                    tooltip=f"Train on {TRAINING_MOTIONS[name].label.lower()}")
            for key, (name, short) in MOTION_KEYS.items()
        ),
        Binding("4", f"motion('{DESIGNED}')", "Designed", group=MOTION_GROUP,
                tooltip="Train on the designed motion (after d, t)"),
        # Before there is a designed motion, 4 says how to make one rather than doing nothing.
        Binding("4", "explain_design", show=False),
        # Priority, and not claimed by number fields, so these work while one has focus.
        Binding("r", "reset", "Reset", priority=True,
                tooltip="Back to the lesson: rich motion, noise 0, 24 samples, seed 7, its joint and plain fit"),
        # On a log, out of the footer (80 columns keep Close log and Export): the help and the palette list it.
        Binding("r", "reset_log", "Reset the log's fit", priority=True, show=False,
                tooltip="On a log: refit it with the log defaults (jointid --csv's model, unconstrained)"),
        Binding("question_mark", "help", "Help", key_display="?", priority=True,
                tooltip="Keys, controls, model and things to try"),
        Binding("q", "quit", "Quit", priority=True, tooltip="Leave the explorer"),
        # The analysis views; s and m are not number characters, so they work in a number
        # field too; e reaches the field only after typing there (1e-2), so it opens the view otherwise.
        Binding("s", "sweep", "Sweep", priority=True, group=VIEWS_GROUP,
                tooltip="Seed sweep: this experiment under many noise seeds"),
        Binding("m", "matrix", "Matrix", priority=True, group=VIEWS_GROUP,
                tooltip="Cross-excitation: fit each motion, predict every motion"),
        Binding("e", "residuals", "Residuals", group=VIEWS_GROUP, tooltip="Training residuals against t, q, qd, qdd"),
        Binding("l", "ladder", "Ladder", priority=True, group=VIEWS_GROUP,
                tooltip="Fit every model of the ladder, BIC's choice, and a simulation of each"),
        Binding("d", "design", "Design", priority=True, group=VIEWS_GROUP,
                tooltip="Design the motion that reveals the parameters best within the joint's limits"),
        # While a log is shown the sweep and the matrix are off (dimmed in the footer, left out of
        # a tight one, so 80 columns keep Close log and Export); these keys then say why.
        Binding("s", "explain_synthetic('The seed sweep')", show=False, priority=True),
        Binding("m", "explain_synthetic('The cross-excitation matrix')", show=False, priority=True),
        Binding("p", "physics", "Physics", priority=True,
                tooltip="Missing physics of the true joint, the fitted model, the sign constraint"),
        # Not in the footer (80 columns have no room; the physics dialog has the same choice).
        Binding("k", "constrain", "Constrain", priority=True, show=False,
                tooltip="Fit subject to the sign rules, or not (toggle)"),
        # c is active only while a log is shown (check_action).
        Binding("ctrl+o", "open_log", "Open log", priority=True,
                tooltip="Load a CSV log, a ROS bag joint or a WPILib data log as training or held-out data, or as "
                "another run"),
        Binding("c", "close_log", "Close log",
                tooltip="Leave the log and return to the synthetic experiment"),
        # Not in the footer (80 columns have no room): the status under the charts names it.
        Binding("n", "notes", "Notes", priority=True, show=False,
                tooltip="The log's notes: how it was read, filtered and checked, and what the fit left out"),
        # Not in the footer (80 columns have no room): a voltage log's note names it, the help and the palette list it.
        Binding("g", "gains", "Gains", priority=True, show=False,
                tooltip="A log's WPILib feedforward gains: kS, kV, kA, and kG of an arm or elevator (a voltage log, "
                "or a torque log with --motor)"),
        # Only with several runs (check_action); the log note names it.
        Binding("u", "runs", "Runs", priority=True, show=False,
                tooltip="Several runs: each run's fit beside the pooled one; a digit there shows a run"),
        Binding("ctrl+s", "export", "Export", priority=True,
                tooltip="Save the fit as JSON and the screen as SVG into a folder"),
        # Not in the footer (80 columns have no room); the palette lists it as Write report.
        Binding("ctrl+r", "write_report", "Write report", priority=True, show=False,
                tooltip="Write an HTML report of what is shown (settings or log, fit, charts, checks) into the "
                "current folder"),
    ]

    def __init__(self, settings: Settings = DEFAULT_SETTINGS, logs: LoadedLogs | PooledRuns | None = None) -> None:
        """Create the screen.

        Args:
            settings: Settings to open at.
            logs: A loaded log to show first (`jointid --csv`), or several runs (`--csv` repeated).
        """
        super().__init__()
        self.settings = settings
        """The synthetic experiment's settings (kept while a log is shown)."""
        self.runs = logs if hasattr(logs, "runs") else None
        """Several runs of one joint (studies.runs.PooledRuns) when loaded; `logs` is then the run shown."""
        self.logs = logs.runs[0] if self.runs is not None else logs
        """The loaded log and its fit; while set, it is the source shown."""
        self.result: FitResult | None = None
        """The fit on screen, of whichever source is shown."""
        self._known_joint = settings.true_joint
        self._title_text = ""
        self._shown_once = False
        self.designed = None if isinstance(settings.motion, str) else settings.motion
        """The designed FourierMotion, the motion list's fourth entry once there is one."""
        self.design_view_state: tuple = (None, None, "d")
        """The design view's last (result, limit fields, criterion), shown again when it reopens."""
        self.synthetic_model: str | None = None
        """The synthetic experiment's model while a log opened over it with Ctrl+O is shown (the log has its own),
        given back when the log is left; None when no log replaced it."""
        self.loading_request: LoadRequest | None = None
        """The request being loaded (one at a time: the progress dialog covers the screen)."""
        self.last_reading: LoadRequest | None = None
        """The request of the last log loaded with Ctrl+O: the dialog starts at its effort, zero, direction and unit,
        so a held-out log or another run is read as it was."""

    def compose(self) -> ComposeResult:
        """Side panel with controls and readouts, chart column, too-small message, footer."""
        # Size classes before the children are styled, so the first resize restyles nothing.
        self.update_classes(size_classes(*self.app.size))
        compact = self.has_class("-compact")
        # A Static, not Textual's Header: one widget instead of four, the same line of text.
        yield Static(self.app.format_title(self.app.title, self.app.sub_title), id="title")
        with Horizontal(id="main"):
            with Vertical(id="side"):
                yield ChoiceList(
                    [*((f"motion-{name}", motion.label) for name, motion in TRAINING_MOTIONS.items()),
                     (f"motion-{DESIGNED}", "Designed motion"),  # shown once there is one
                     ("motion-log", "Log")],  # shown only while a log is
                    on_choose=self.choose_motion,
                    hidden=("motion-log",) + ((f"motion-{DESIGNED}",) if self.designed is None else ()), id="motion",
                )
                for steps in STEP_RANGES:
                    with Horizontal(classes="field"):
                        yield Static(FIELD_LABELS[steps.field], classes="field--label", markup=False)
                        yield Stepper(steps, on_commit=self.commit_setting, id=steps.field)
                # After the fields, so Tab visits motion, noise, samples, seed, then Reset.
                with Horizontal(id="reset-row"):
                    yield ActionButton("Reset", on_press=self.action_reset, id="reset")
                    yield Static(STEPPER_HINT, id="stepper-hint", markup=False)
                yield Static("", id="log-note", markup=False)
                yield Static(known_parameters_text(self.settings.true_joint, compact), id="known", markup=False)
                yield ReadoutPanel(id="readouts", compact=compact)
            with Vertical(id="charts"):
                yield TorqueChart(id="training-chart")
                yield TorqueChart(id="heldout-chart")
        yield FittingLine(id="status", min_lines=STATUS_LINES)
        yield Static("", id="too-small", markup=False)
        yield KeyFooter()

    def on_mount(self) -> None:
        """Show the initial source."""
        self.show_source()

    def on_screen_resume(self, event: ScreenResume) -> None:
        """The first time the screen shows, keep its styles: each widget was styled as it mounted.

        Textual restyles every widget of a screen that resumes, for CSS that changed while it was
        covered; on the first resume nothing has covered it. Skipping that restyle buys 0.026 of the
        explorer's start (bench_startup_budget first-resume-keeps-styles): under the budget's 5 %, kept
        for the explorer's 1.10x start-up limit (benchmarks/README.md, "Start-up budget"). Later resumes
        (a dialog or view closing) restyle as usual. Runs before Textual's own handler.
        """
        if not self._shown_once:
            self._shown_once = True
            event.refresh_styles = False

    def on_resize(self) -> None:
        """Compact rows on small terminals; a plain message when the terminal is too small to read."""
        width, height = self.size
        classes = size_classes(width, height)
        compact = classes["-compact"]
        switched = compact != self.has_class("-compact")
        if switched:
            self.show_known()
            self.query_one(ReadoutPanel).set_compact(compact)
        self.update_classes(classes)  # restyles the screen only when a class changes
        if switched:
            self.show_status()  # reads the new -compact class
        if classes["-too-small"]:
            self.query_one("#too-small", Static).update(
                f"Please enlarge the terminal.\n\n"
                f"The jointid explorer needs at least {MIN_SIZE[0]} x {MIN_SIZE[1]} characters; "
                f"this one is {width} x {height}.\n\nPress q to quit."
            )

    # --- the source and its one push-down ---------------------------------------------

    def set_settings(self, settings: Settings) -> None:
        """Show the synthetic experiment at `settings` (leaving a log)."""
        if settings == self.settings and self.logs is None and self.result is not None:
            return
        self.settings, self.logs, self.runs = settings, None, None
        self.show_source()

    def set_logs(self, logs: LoadedLogs | None) -> None:
        """Show a loaded log, or go back to the synthetic experiment with None (leaving any runs)."""
        self.logs, self.runs = logs, None
        self.show_source()

    def set_runs(self, runs: PooledRuns, shown: int) -> None:
        """Show one of several runs (its own fit), the others and their pooled fit a key (u) away."""
        self.runs, self.logs = runs, runs.runs[shown]
        self.show_source()

    def show_run(self, index: int) -> None:
        """The runs view's digit: show that run."""
        if self.runs is not None and 0 <= index < len(self.runs.runs):
            self.set_runs(self.runs, index)

    def show_source(self) -> None:
        """Fit the source shown (or take the log's fit) and push the result down to every widget."""
        logs, settings = self.logs, self.settings
        if logs is None:
            self.synthetic_model = None  # the synthetic experiment is shown with its own
        if (logs is not None) != self.has_class("-log"):
            self.refresh_bindings()  # Close log appears or goes
        self.set_class(logs is not None, "-log")
        self.set_class(logs is not None and logs.heldout is None, "-no-heldout")
        self.set_class(settings.joint_model.size > PLAIN.size or settings.true_joint.has_missing_physics
                       or settings.constrained, "-extended")
        motion = self.query_one("#motion", ChoiceList)
        run = "" if self.runs is None else f"Run {self.runs.runs.index(logs) + 1}: "
        motion.set_option("motion-log", label=None if logs is None else f"{run or 'Log: '}{logs.name}",
                          shown=logs is not None)
        motion.set_option(f"motion-{DESIGNED}", shown=self.designed is not None)
        self.set_class(self.designed is not None, "-designed")  # its row in the motion list costs Reset's on short screens
        motion.show_pressed("motion-log" if logs is not None else f"motion-{settings.motion_name}")
        for steps in STEP_RANGES:  # by id: a type query walks the whole screen (0.3 ms)
            stepper = self.query_one(f"#{steps.field}", Stepper)
            stepper.disabled = logs is not None
            stepper.show_value(FROM_LOG if logs is not None else getattr(settings, steps.field))
        self.show_log_note()
        if settings.true_joint != self._known_joint:  # a Static update repaints; skip it when equal
            self._known_joint = settings.true_joint
            self.show_known()
        if logs is None:
            result = cached_experiment(settings)
            training, heldout = training_chart(result), heldout_chart(result)
        else:
            result = logs.result
            columns = max(self.app.size.width, 80)  # a chart is never wider than the terminal
            training = log_training_chart(logs, columns=columns)
            heldout = heldout_chart(result, log_name=logs.heldout_name, columns=columns)
        self.result = result
        self.show_title()
        self.query_one("#training-chart", TorqueChart).show(training)
        if heldout is not None:  # without a held-out log its chart is hidden (-no-heldout)
            self.query_one("#heldout-chart", TorqueChart).show(heldout)
        linear = logs is not None and logs.training.position_unit == "metres"  # an elevator's speed is in m/s
        self.query_one(ReadoutPanel).show(readouts(result, linear), precision(result))
        self.show_status()

    def show_status(self) -> None:
        """The status sentence of the fit shown (a log's names its files in full only on roomy screens)."""
        compact = self.has_class("-compact")
        # The full sentence when it fits the rows, else one that names what the readouts beside show in figures:
        # a noisy fit's or a five-term model's sentence wrapped to five or six lines at 80 columns (and a
        # constrained one's at 120) and pushed the readouts off. A log's is the short one on compact screens.
        if self.logs is not None:
            variants = (Content(log_status(self.logs, compact=compact)),)
        else:
            variants = (Content(status_message(self.result)), Content(compact_status(self.result)))
        line = self.query_one("#status", FittingLine)
        # A model with more terms fills the compact side panel's rows: its status gives one back.
        terse = compact and self.has_class("-extended") and self.logs is None
        line.set_min_lines(COMPACT_EXTENDED_STATUS_LINES if terse else STATUS_LINES)
        line.show(variants)

    def show_title(self) -> None:
        """The title line, naming the fitted model and the constraint when they are not the lesson's."""
        settings, title = self.settings, self.app.format_title(self.app.title, self.app.sub_title)
        notes = ([f"model {settings.model}"] if settings.model != DEFAULT_SETTINGS.model else []) + (
            ["constrained"] if settings.constrained else [])
        text = f"{title} · {', '.join(notes)}" if notes else title
        if text != self._title_text:  # a Static update repaints; skip it when equal
            self._title_text = text
            self.query_one("#title", Static).update(text)

    def show_known(self) -> None:
        """The synthetic joint beside the controls (its missing physics included when present)."""
        self.query_one("#known", Static).update(
            known_parameters_text(self.settings.true_joint, self.has_class("-compact")))

    def show_log_note(self) -> None:
        """The note on the synthetic controls, which give way while a log is shown."""
        if self.logs is not None:
            runs = () if self.runs is None else (runs_note(self.runs, self.runs.runs.index(self.logs)),)
            self.query_one("#log-note", Static).update("\n".join((log_note(self.logs), *runs)))

    # --- the controls' callbacks and the actions --------------------------------------

    def commit_setting(self, field: str, value: float) -> None:
        """A number field committed a value (its callback)."""
        self.set_settings(replace(self.settings, **{field: value}))

    def change_fit(self, field: str, value) -> None:
        """A setting from the physics dialog or the constraint key: a log is refitted with the new model
        or constraint (the true joint's physics apply to synthetic data only)."""
        settings = replace(self.settings, **{field: value})
        if self.logs is None or field not in ("model", "constrained"):
            self.set_settings(settings)
            return
        self.settings = settings
        if self.runs is not None:
            self.refit_runs_worker(self.runs, self.runs.runs.index(self.logs), settings)
            return
        self.refit_worker(self.logs, settings)

    @work(thread=True, exclusive=True, group="log-refit")
    def refit_runs_worker(self, runs: PooledRuns, shown: int, settings: Settings) -> None:
        """Refit every run with the settings' model and constraint off the main thread, then pool them again;
        shown if nothing changed meanwhile."""
        from jointid.studies.runs import fit_runs

        first = runs.runs[0]
        try:
            refitted = fit_runs([run.training for run in runs.runs], settings.joint_model, first.filtering,
                                first.exclusion, settings.constrained, weighting=runs.weighting)
        except ValueError as error:  # LogError: numbers beyond double precision
            self.app.call_from_thread(self.notify, str(error).splitlines()[0], title="Runs not refitted",
                                      severity="error")
            return
        self.app.call_from_thread(self.finish_runs_refit, runs, shown, settings, refitted)

    def finish_runs_refit(self, runs: PooledRuns, shown: int, settings: Settings, refitted: PooledRuns) -> None:
        """Show the runs refitted unless other data, a model or constraint was chosen while they were."""
        if self.runs is runs and self.settings == settings:
            self.set_runs(refitted, shown)

    @work(thread=True, exclusive=True, group="log-refit")
    def refit_worker(self, logs: LoadedLogs, settings: Settings) -> None:
        """Refit the shown log with the settings' model and constraint off the main thread (a large log's fit
        and its sensitivity refits take seconds); the result is shown if nothing changed meanwhile."""
        from jointid.studies.log_fit import fit_logs

        try:
            refitted = fit_logs(logs.training, logs.heldout, settings.joint_model, settings.constrained,
                                logs.filtering)
        except ValueError as error:  # LogError: numbers beyond double precision
            self.app.call_from_thread(self.notify, str(error).splitlines()[0], title="Log not refitted",
                                      severity="error")
            return
        self.app.call_from_thread(self.finish_refit, logs, settings, refitted)

    def finish_refit(self, logs: LoadedLogs, settings: Settings, refitted: LoadedLogs) -> None:
        """Show a refit unless another log, model or constraint was chosen while it ran."""
        if self.logs is logs and self.settings == settings:
            self.set_logs(refitted)

    def choose_motion(self, button_id: str) -> None:
        """The motion list's choice (choosing the log's own entry changes nothing)."""
        if button_id != "motion-log":
            self.action_motion(button_id.removeprefix("motion-"))

    def apply_settings(self, settings: Settings) -> None:
        """Set every control at once (reset, tour stops); leaves a log."""
        self.set_settings(settings)

    def synthetic_settings(self) -> Settings:
        """The settings to leave a log for: the synthetic experiment's model given back when the log was opened
        over it with Ctrl+O (the log was fitted with its own)."""
        if self.logs is None or self.synthetic_model is None:
            return self.settings
        return replace(self.settings, model=self.synthetic_model)

    def action_motion(self, name: str) -> None:
        """Select a training motion, the designed one included (leaving a log)."""
        if name == DESIGNED:
            if self.designed is None:
                self.notify("No designed motion yet: press d to design one, then t to train on it.",
                            severity="warning")
                return
            self.set_settings(replace(self.synthetic_settings(), motion=self.designed))
            return
        self.set_settings(replace(self.synthetic_settings(), motion=name))

    def action_design(self) -> None:
        """Open the design view for the current samples, noise and model."""
        from .design import DesignScreen

        result, limits, criterion = self.design_view_state
        self.app.push_screen(DesignScreen(self.settings, self.train_on_design, result, limits, criterion))

    def train_on_design(self, result, limits: dict, criterion: str) -> None:
        """The design view's `t`: the design joins the motion list as its fourth motion and is trained on."""
        self.design_view_state = (result, dict(limits), criterion)
        self.designed = result.motion
        self.action_motion(DESIGNED)
        self.notify("Training on the designed motion (4 in the motion list). In the design view (d), w saves it "
                    "as a motion file.", title="Designed motion")

    def action_reset(self) -> None:
        """Back to the lesson's experiment, as the tour's first stop: the four controls, and the lesson's joint
        (no missing physics), the plain model and an unconstrained fit, saying so when those were changed; on a log,
        back to the log defaults. The focus goes to the motion list, where the footer's keys act."""
        self.query_one("#motion", ChoiceList).focus()  # not a number field, which would take the next digit typed
        settings = self.settings
        undone = [what for what, changed in (
            ("no missing physics", settings.true_joint.has_missing_physics),
            ("the plain model", settings.model != DEFAULT_SETTINGS.model),
            ("an unconstrained fit", settings.constrained != DEFAULT_SETTINGS.constrained)) if changed]
        self.set_settings(DEFAULT_SETTINGS)
        if undone:
            self.notify(f"Back to the lesson's joint and fit: {', '.join(undone)} (p changes them).", title="Reset")

    def log_defaults(self) -> str:
        """The model the log shown is fitted with unless another is chosen: `jointid --csv`'s for its effort."""
        return default_log_model(self.logs.result.model.effort.name)

    def action_reset_log(self) -> None:
        """r on a log: refit it with the log defaults (the model for its effort, unconstrained), saying what that
        undid; the log stays (c leaves it), and the focus goes to the motion list, as after Reset."""
        self.query_one("#motion", ChoiceList).focus()
        model, settings = self.log_defaults(), self.settings
        undone = [what for what, changed in ((f"model {model}", settings.model != model),
                                             ("an unconstrained fit", settings.constrained)) if changed]
        if not undone:
            self.notify(f"The log is fitted with its defaults already: model {model}, unconstrained (p changes them; "
                        "c leaves the log).", title="Reset")
            return
        self.settings = replace(settings, model=model, constrained=False)
        if self.runs is not None:
            self.refit_runs_worker(self.runs, self.runs.runs.index(self.logs), self.settings)
        else:
            self.refit_worker(self.logs, self.settings)
        self.notify(f"Back to the log defaults: {', '.join(undone)} (p changes them; c leaves the log).",
                    title="Reset")

    def action_explain_design(self) -> None:
        """4 before a design exists: say how to make one."""
        self.action_motion(DESIGNED)

    def action_physics(self) -> None:
        """Open the physics dialog: the true joint's missing physics, the fitted model, the constraint."""
        from .physics import PhysicsScreen

        def changed(field: str, value) -> None:
            self.change_fit(field, value)
            dialog.show(self.settings)

        dialog = PhysicsScreen(self.settings, changed)
        self.app.push_screen(dialog)

    def action_constrain(self) -> None:
        """Toggle the fit's sign constraint."""
        self.change_fit("constrained", not self.settings.constrained)

    def action_ladder(self) -> None:
        """Open the model-ladder view on the data shown (the synthetic experiment, the log, or its runs pooled)."""
        from jointid.present.text import settings_header
        from jointid.synthetic.samples import training_data, validation_data

        from .ladder import LadderScreen

        if self.logs is None:
            settings = self.settings
            self.app.push_screen(LadderScreen(settings_header(settings), training_data(settings),
                                              validation_data(settings.true_joint), noise_bound=settings.noise,
                                              joint=settings.true_joint))
        elif self.runs is not None:  # several runs: their pooled ladder, as `jointid compare` gives it
            self.app.push_screen(LadderScreen(f"{len(self.runs.runs)} runs pooled", runs=self.runs))
        else:
            self.app.push_screen(LadderScreen(f"log {self.logs.name}", logs=self.logs))

    def action_help(self) -> None:
        """Open the help screen."""
        from .help import HelpScreen  # Markdown is only needed when help is asked for

        self.app.push_screen(HelpScreen(self.BINDINGS))

    # The views are imported when first opened, which keeps start-up fast.
    def action_sweep(self) -> None:
        """Open the seed-sweep view for the current settings."""
        if self.needs_synthetic("The seed sweep"):
            return
        from .sweep import SweepScreen

        self.app.push_screen(SweepScreen(self.settings))

    def action_matrix(self) -> None:
        """Open the cross-excitation view for the current noise, samples and seed."""
        if self.needs_synthetic("The cross-excitation matrix"):
            return
        from .matrix import MatrixScreen

        self.app.push_screen(MatrixScreen(self.settings))

    def action_residuals(self) -> None:
        """Open the residual view of the current fit."""
        from jointid.present.text import settings_header

        from .residuals import ResidualScreen

        source = settings_header(self.settings) if self.logs is None else f"log {self.logs.name}"
        self.app.push_screen(ResidualScreen(self.result, source))

    async def action_quit(self) -> None:
        """Leave the explorer."""
        await self.app.action_quit()

    # --- logs ---------------------------------------------------------------------------

    def check_action(self, action: str, parameters: tuple) -> bool | None:
        """Close log exists only while a log is shown, 4 once a motion is designed; the sweep and the matrix are off
        (None) while one is, and r resets the log's fit instead of the lesson's."""
        if action in ("close_log", "notes", "gains"):
            return self.logs is not None
        if action == "runs":
            return self.runs is not None
        if action == "motion" and parameters == (DESIGNED,):  # 4 appears once there is a designed motion
            return self.designed is not None
        if action in ("sweep", "matrix"):
            return True if self.logs is None else None
        if action in ("reset", "reset_log"):  # one r: the lesson's Reset, or on a log the log's own
            return (self.logs is None) == (action == "reset")
        if action == "explain_synthetic":
            return self.logs is not None
        if action == "explain_design":
            return self.designed is None
        return super().check_action(action, parameters)

    def action_explain_synthetic(self, view: str) -> None:
        """Say why a view of synthetic settings does not open while a log is shown."""
        self.needs_synthetic(view)

    def action_notes(self) -> None:
        """Open the log's notes in their own view."""
        from .notes import NotesScreen  # only a log's fit has notes

        self.app.push_screen(NotesScreen(self.logs))

    def session_drive(self):
        """The motor the explorer was started with (`--motor`), or None."""
        conventions = self.app.conventions
        return None if conventions is None else conventions.motor

    def action_gains(self) -> None:
        """Open the gains view: the WPILib feedforward gains of the log shown (and the motor's physical parameters
        behind a voltage log's); a notification when the fit gives none (a torque log without a motor)."""
        from jointid.studies.gains import GainsError

        from .gains import GainsScreen  # only a log's fit has gains

        fit = self.logs if self.runs is None else self.runs  # several runs: their pooled fit's gains
        try:
            sections = gains_sections(fit, self.session_drive())
        except GainsError as error:
            self.notify(str(error), title="No gains", severity="warning")
            return
        title = self.logs.name if self.runs is None else f"{len(self.runs.runs)} runs pooled"
        self.app.push_screen(GainsScreen(title, sections))

    def action_runs(self) -> None:
        """Open the runs view: each run's fit beside the pooled one."""
        from .runs import RunsScreen  # only several runs have it

        self.app.push_screen(RunsScreen(self.runs, self.show_run))

    def action_close_log(self) -> None:
        """Return from the log to the synthetic experiment."""
        if self.logs is None:
            self.notify("No log is loaded.", severity="warning")
            return
        self.settings = self.synthetic_settings()
        self.set_logs(None)

    def needs_synthetic(self, view: str) -> bool:
        """True (after saying why) when a view of synthetic settings is asked for while a log is shown."""
        if self.logs is None:
            return False
        self.notify(f"{view} needs a synthetic experiment: press 1, 2, 3 or c to leave the log.",
                    severity="warning")
        return True

    def action_open_log(self) -> None:
        """Choose a training or held-out log to load (in a browser: from the server's --data folder only)."""
        from .open_log import OpenLogScreen

        folder = os.path.dirname(os.path.abspath(self.logs.training.path)) if self.logs else None
        data = None
        if self.app.is_web:
            from ..web import NO_DATA_FOLDER, data_folder, is_inside

            data = data_folder()
            if data is None:
                self.notify(NO_DATA_FOLDER, title="Open log", severity="warning")
                return
            folder = folder if folder is not None and is_inside(folder, data) else str(data)
        conventions, last = self.app.conventions, self.last_reading
        if last is not None:  # as the last log was read (the command line's --columns and --motor stay)
            from jointid.logs.conventions import LogConventions

            conventions = replace(conventions or LogConventions(), angle=last.angle,
                                  effort=None if last.effort.kind == "torque" else last.effort)
        self.app.push_screen(OpenLogScreen(folder, data_folder=data, on_request=self.start_loading,
                                           heldout_allowed=self.logs is not None and self.runs is None,
                                           run_allowed=self.logs is not None,
                                           derivatives=self.app.derivatives, filtering=self.app.filtering,
                                           conventions=conventions,
                                           degrees=last is not None and last.degrees))

    def start_loading(self, request: LoadRequest | None, chooser: Screen | None = None) -> None:
        """Load a chosen file in a worker behind a progress dialog; the dialog it was chosen in (`chooser`)
        closes once it is shown, and stays, with its path, when it cannot be."""
        if request is None:
            return
        if self.app.is_web:  # the dialog checks as the path is typed; this is the check no path can go around
            from ..web import NO_DATA_FOLDER, OutsideDataFolder, data_folder, inside

            data = data_folder()
            try:
                if data is None:
                    raise OutsideDataFolder(NO_DATA_FOLDER)
                inside(request.path, data)
            except OutsideDataFolder as error:
                self.notify(str(error), title="Log not loaded", severity="error")
                return
        from .loading import LoadingScreen

        dialog = LoadingScreen(request.path, chooser)
        self.loading_request = request  # remembered once the log is shown (last_reading)
        self.app.push_screen(dialog)
        self.load_worker(request, self.logs if self.runs is None else self.runs, dialog, self.model_for(request))

    def model_for(self, request: LoadRequest) -> JointModel:
        """The model a chosen log is fitted with, as `jointid --csv` would: a held-out log or another run, the fit's
        shown; a new training log, the log defaults for its effort, unless a model other than the shown log's
        defaults was chosen for it (p, or the command line's --model), which carries over as --model would."""
        from jointid.logs.request import TRAINING
        from jointid.model.terms import model_named

        if request.role != TRAINING or (self.logs is not None and self.settings.model != self.log_defaults()):
            return self.settings.joint_model
        return model_named(default_log_model(request.effort.kind))

    @work(thread=True, exclusive=True, group="log-load")
    def load_worker(self, request: LoadRequest, current: LoadedLogs | PooledRuns | None,
                    dialog: LoadingScreen, model: JointModel) -> None:
        """Read and fit the log off the main thread with `model`; the outcome is applied on the main thread."""
        from jointid.logs.request import HELDOUT, RUN
        from jointid.logs.table import LoadCancelled
        from jointid.studies.log_fit import load_request

        app = self.app
        progress = lambda done, total: app.call_from_thread(dialog.advance, done, total)  # noqa: E731
        try:
            if request.role == RUN:  # one more run of the joint: pooled with the runs (or the log) shown
                from jointid.logs.request import load_joint_log
                from jointid.studies.runs import add_run

                if current is None:
                    raise ValueError(f"{request.path}: another run needs a training log first")
                log = load_joint_log(request, progress=progress, cancel=dialog.cancelled.is_set)
                if dialog.cancelled.is_set():  # as load_request: no refit is started after an Escape
                    raise LoadCancelled(request.path)
                logs = add_run(current, log, model, self.settings.constrained)
            elif request.wpilog and request.role != HELDOUT:  # a SysId data log opens as its tests, pooled
                from jointid.studies.sysid import load_training_request

                logs = load_training_request(request, model, self.settings.constrained,
                                             progress, dialog.cancelled.is_set)
            elif hasattr(current, "runs"):  # several runs: each is predicted by the others; a new log replaces them
                if request.role == HELDOUT:
                    raise ValueError(f"{request.path}: with several runs each run is predicted by the others; "
                                     "no held-out log (c leaves the runs)")
                logs = load_request(request, None, model, self.settings.constrained,
                                    progress, dialog.cancelled.is_set)
            else:
                logs = load_request(request, current, model, self.settings.constrained,
                                    progress, dialog.cancelled.is_set)
        except LoadCancelled:
            app.call_from_thread(self.finish_loading, dialog, None, "Loading cancelled; nothing changed.")
        except (ValueError, OSError) as error:  # LogError is a ValueError with a one-line text
            app.call_from_thread(self.finish_loading, dialog, None, str(error).splitlines()[0])
        else:
            app.call_from_thread(self.finish_loading, dialog, logs, None)

    def finish_loading(self, dialog: LoadingScreen, logs: LoadedLogs | PooledRuns | None,
                       problem: str | None) -> None:
        """Close the progress dialog and show the new logs (or the run added), or say why the current data stay."""
        if logs is not None and dialog.cancelled.is_set():
            # Escape came during the fit, which cannot stop part-way: its result is dropped, as the dialog said.
            logs, problem = None, "Loading cancelled; nothing changed."
        if dialog.is_attached:
            dialog.dismiss()
        if logs is None:  # the Open dialog, if the file was chosen there, shows again with its path
            cancelled = dialog.cancelled.is_set()
            self.notify(problem, title="Log not loaded", severity="warning" if cancelled else "error")
            return
        if dialog.chooser is not None and dialog.chooser.is_attached:
            dialog.chooser.dismiss()
        self.last_reading = self.loading_request
        if hasattr(logs, "runs") and logs.runs[0].training.name != shown_name(os.path.basename(
                logs.runs[0].training.path)) \
                and all(run.training.path == dialog.path for run in logs.runs):
            # A SysId data log's tests (no other runs come from one file): shown from the first, in the model
            # they were fitted with.
            if self.logs is None and self.synthetic_model is None:
                self.synthetic_model = self.settings.model
            self.settings = replace(self.settings, model=logs.runs[0].result.model.name)
            self.set_runs(logs, 0)
            self.notify(f"{len(logs.runs)} SysId tests of {shown_name(dialog.path)}, fitted alone and pooled; u: every test",
                        title="SysId log loaded")
            return
        if hasattr(logs, "runs"):
            self.set_runs(logs, len(logs.runs) - 1)
            self.notify(f"{logs.runs[-1].source_texts()[0]}; u: every run and the pooled fit",
                        title=f"Run {len(logs.runs)} added")
            return
        if self.logs is None and self.synthetic_model is None:  # given back when the log is left
            self.synthetic_model = self.settings.model
        self.settings = replace(self.settings, model=logs.result.model.name)  # p, the title and later logs see it
        self.set_logs(logs)
        # The texts of the command line's first lines: the samples fitted counted as the note counts them.
        training, *heldout = logs.source_texts()
        if heldout and logs.heldout.path == dialog.path:
            self.notify(heldout[0], title="Held-out log loaded")
        else:
            self.notify(training, title="Log loaded")

    # --- export -------------------------------------------------------------------------

    def export_stem(self) -> str:
        """The file name exports of what is shown start with: 'train-fit', 'jointid-slow-0.20-24-7'."""
        if self.runs is not None:
            return f"{Path(self.runs.runs[0].training.path).stem}-runs-fit"
        if self.logs is not None:
            return f"{Path(self.logs.training.path).stem}-fit"
        s = self.settings
        model = "" if s.model == DEFAULT_SETTINGS.model else f"-{s.model}"
        return f"jointid-{s.motion_name}-{s.noise:.2f}-{s.samples}-{s.seed}{model}"

    def export_content(self) -> tuple[str, dict]:
        """File stem and JSON document of the current result, as `jointid fit [--csv] --json` prints it."""
        if self.runs is not None:
            from jointid.present.runs import runs_document

            return self.export_stem(), runs_document(self.runs)
        if self.logs is not None:
            from jointid.present.documents import logs_document

            return self.export_stem(), logs_document(self.logs)
        from jointid.present.documents import fit_document  # json and the documents: only when exporting

        return self.export_stem(), fit_document(self.result, settings=self.settings)

    def action_export(self) -> None:
        """Export the fit as JSON and the screen as SVG into a chosen folder."""
        from .export import ExportScreen

        svg = self.app.export_screenshot()  # before the dialog covers the screen
        stem, document = self.export_content()
        if self.app.is_web:  # in a browser the files are the browser's downloads, never the server's
            from ..web import deliver_export

            json_name, svg_name = deliver_export(self.app, stem, document, svg)
            self.notify(f"Your browser downloads {shown_name(json_name)} and {shown_name(svg_name)}", title="Exported")
            return
        self.app.push_screen(ExportScreen(stem), lambda folder: self.write_export(folder, stem, document, svg))

    def write_export(self, folder: str | None, stem: str, document: dict, svg: str) -> None:
        """Write the export pair and say where, or say why not."""
        if folder is None:
            return
        from jointid.files import ExportError

        from .export import write_export

        try:
            json_path, svg_path = write_export(folder, stem, document, svg)
        except ExportError as error:
            self.notify(str(error), title="Nothing exported", severity="error")
            return
        self.notify(f"Wrote {shown_name(str(json_path))} and {shown_name(str(svg_path))}", title="Exported")

    def action_write_report(self) -> None:
        """Write the report of what is shown (`jointid report` of the same source) into the current folder (in a
        browser: a download)."""
        self.notify("Drawing the charts; a notification says where the report is.", title="Writing the report")
        # The source as it is now: the worker reads only these immutable results, never the screen.
        self.write_report(self.export_stem().removesuffix("-fit") + "-report", self.runs, self.logs, self.result,
                          self.settings)

    @work(thread=True, exclusive=True, group="report")
    def write_report(self, stem: str, runs, logs, result, settings) -> None:
        """Build and write the report in a thread (drawing its charts takes about a second); notify where, or why
        not."""
        from jointid.files import ExportError
        from jointid.present.report_charts import ReportExtraMissing

        from .export import write_report_page

        if self.app.is_web:  # in a browser the page is a download, never a file on the server
            from ..web import deliver_report

            try:
                page = report_page(runs, logs, result, settings, self.session_drive())
            except ReportExtraMissing as error:
                self.app.call_from_thread(self.notify, str(error), title="No report written", severity="error")
                return
            name = self.app.call_from_thread(deliver_report, self.app, stem, page)
            self.app.call_from_thread(self.notify, f"Your browser downloads {shown_name(name)}", title="Report written")
            return
        try:
            folder = os.getcwd()
        except OSError:  # the folder was removed under the explorer: the write says so, in one line
            folder = os.curdir
        try:
            path = write_report_page(folder, stem, report_page(runs, logs, result, settings, self.session_drive()))
        except (ExportError, ReportExtraMissing) as error:
            self.app.call_from_thread(self.notify, str(error), title="No report written", severity="error")
            return
        self.app.call_from_thread(self.notify, f"Wrote {shown_name(str(path))}", title="Report written")
