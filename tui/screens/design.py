"""The design view: the Fourier-series motion that reveals the parameters best within the joint's limits.

The limits and the criterion are fields here; the optimiser runs in a child
process (`jointid.studies.design_process`), so it never holds the GIL the app's loop
needs, waited on by a worker thread, with a progress bar; cancelling kills the
process, and so does closing the view. The result shows q(t) against
rich motion's, both motions' expected standard errors, the limits' margins and
the verdict (the `cond` criterion's counter-example included). `t` trains the
explorer on the design (it joins the motion list as a fourth motion); `w`
saves it as a motion file for `--motion-file`.
"""

from __future__ import annotations

import math
from contextlib import suppress
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Callable

from textual import work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical, VerticalScroll
from textual.css.query import NoMatches
from textual.screen import Screen
from textual.widgets import ProgressBar, Static
from textual.worker import Worker, WorkerState, get_current_worker

from jointid.options import CRITERIA, DEFAULT_NOISE, RICH_ENVELOPE, SettingsError, parse_float
from jointid.present.design import DESIGN_INTRO, design_chart
from jointid.synthetic.settings import Settings

from ..widgets.direct_controls import ChoiceList
from ..widgets.footer import KeyFooter
from ..widgets.small_plots import SmallPlot
from ..widgets.stepper import Stepper, StepRange


@dataclass(frozen=True)
class LimitRange(StepRange):
    """A limit field's range; limits are not experiment settings, so the range parses its own text."""

    def parse(self, text: str) -> float:
        """Typed text as a limit in range, or raise SettingsError (one line)."""
        text = text.strip()
        try:
            value = parse_float(text)
        except ValueError:
            value = math.nan
        if not (math.isfinite(value) and self.low <= value <= self.high and (value > 0 or self.field == "tau_max")):
            raise SettingsError(self.field, f"{self.label} must be a number {self.describe()}"
                                f"{' (0: no limit)' if self.field == 'tau_max' else ', above 0'}; got {text!r}")
        return value


LIMIT_FIELDS = (
    LimitRange("q_max", 0.0, 3.14, 0.05, 0.25, decimals=2, unit="rad", label="|q| max"),
    LimitRange("qd_max", 0.0, 20.0, 0.1, 1.0, decimals=2, unit="rad/s", label="|qd| max"),
    LimitRange("qdd_max", 0.0, 50.0, 0.1, 1.0, decimals=2, unit="rad/s²", label="|qdd| max"),
    LimitRange("tau_max", 0.0, 100.0, 0.5, 5.0, decimals=2, unit="N m", label="|tau| max"),
)
"""The limit fields: angle, speed, acceleration, and the actuator torque (0: no torque limit)."""
FIELD_LABELS = {"q_max": "|q| max (rad)", "qd_max": "|qd| max (rad/s)", "qdd_max": "|qdd| max (rad/s²)",
                "tau_max": "|tau| max (N m, 0 none)"}
"""The label beside each limit field."""
COMMAND_KEYS = "gctw"
"""Keys a limit field passes to the view while nothing is typed in it."""


class DesignScreen(Screen):
    """Design an excitation motion in a worker; show it against rich motion; train on it or save it."""

    CSS_PATH = Path(__file__).parent.parent / "views.tcss"  # read when first opened, not at start-up

    BINDINGS = [
        # Priority: a limit field has focus and would otherwise take Escape.
        Binding("escape", "back", "Cancel / back", priority=True,
                tooltip="Cancel a running design, otherwise return to the explorer"),
        # Not priority: a focused limit field passes these on only while nothing is typed (command_keys).
        Binding("g", "run", "Run", tooltip="Design the motion for these limits and criterion"),
        Binding("c", "cancel", "Cancel", tooltip="Stop a running design"),
        Binding("t", "train", "Train on it",
                tooltip="Add the designed motion to the motion list as a fourth motion and train on it"),
        Binding("w", "save", "Save file",
                tooltip="Save the designed motion as a motion file in the current folder (for --motion-file)"),
    ]

    def __init__(self, settings: Settings, on_train: Callable, result=None, limits: dict | None = None,
                 criterion: str = "d") -> None:
        """Create the view.

        Args:
            settings: The explorer's experiment: the design is for its samples, model and true joint, and its
                noise (or the lesson's 0.20 N m when it has none, so standard errors have a scale).
            on_train: Called with the designed FourierMotion when the user trains on it.
            result: A previous DesignResult to show again.
            limits: The limit fields' values ({'q_max': ...}), default rich motion's envelope and no torque limit.
            criterion: 'd', 'a' or 'cond'.
        """
        super().__init__()
        noise = settings.noise if settings.noise > 0 else DEFAULT_NOISE
        self.experiment = replace(settings, noise=noise, motion="rich", seed=7)
        self.on_train = on_train
        self.result = result
        self.limits = dict(limits or {**RICH_ENVELOPE, "tau_max": 0.0})
        self.criterion = criterion
        self.designer = None
        """The jointid.studies.design_process.DesignProcess that runs this view's designs (started at the first run)."""

    def compose(self) -> ComposeResult:
        """Title; limits, criterion and progress beside the chart; the comparison below; footer."""
        s = self.experiment
        yield Static(f"Excitation design for model {s.model}, {s.samples} samples, noise {s.noise:.2f} N m",
                     id="design-title", markup=False)
        with Horizontal(id="design-top"):
            with Vertical(id="design-controls"):
                for steps in LIMIT_FIELDS:
                    with Horizontal(classes="field"):
                        yield Static(FIELD_LABELS[steps.field], classes="field--label", markup=False)
                        yield Stepper(steps, self.limits[steps.field], on_commit=self.commit_limit,
                                      command_keys=COMMAND_KEYS, id=steps.field)
                yield ChoiceList([(f"criterion-{name}", text.split(" (")[0]) for name, text in CRITERIA.items()],
                                 on_choose=self.choose_criterion, id="criterion")
                with Horizontal(id="design-run"):
                    yield ProgressBar(total=1, show_eta=False, show_percentage=False, id="design-progress")
                    yield Static("g runs the design", id="design-state", markup=False)
            yield SmallPlot(id="design-chart")
        with VerticalScroll(id="design-body"):
            yield Static(DESIGN_INTRO, id="design-table", markup=False)
            yield Static("", id="design-verdict", markup=False)
            yield Static("", id="design-limits", markup=False)
        yield KeyFooter()

    def on_mount(self) -> None:
        """Show the criterion (and a previous result), focus the first limit field."""
        self.query_one("#criterion", ChoiceList).show_pressed(f"criterion-{self.criterion}")
        self.query_one(Stepper).focus()
        if self.result is not None:
            self.show_result(self.result)
        else:
            self.query_one("#design-chart", SmallPlot).show(design_chart(None))

    # --- the fields ---------------------------------------------------------------------

    def commit_limit(self, field: str, value: float) -> None:
        """A limit field committed a value (its callback)."""
        self.limits[field] = value
        self.query_one(f"#{field}", Stepper).show_value(value)

    def choose_criterion(self, option: str) -> None:
        """The criterion list's choice."""
        self.criterion = option.removeprefix("criterion-")
        self.query_one("#criterion", ChoiceList).show_pressed(option)

    # --- running ------------------------------------------------------------------------

    def spec(self):
        """The DesignSpec of the fields; DesignError when the limits admit no design."""
        from jointid.studies.design import DesignSpec, Limits

        tau = self.limits["tau_max"] or None
        return DesignSpec(limits=Limits(self.limits["q_max"], self.limits["qd_max"], self.limits["qdd_max"], tau),
                          criterion=self.criterion, experiment=self.experiment)

    def action_run(self) -> None:
        """Start a design with the current fields (an exclusive worker drops one still running)."""
        from jointid.studies.design import DesignError, budget_overrun

        try:
            spec = self.spec()
        except DesignError as error:
            self.notify(str(error), title="Cannot design", severity="error")
            return
        # The command line's work budget: the explorer's samples and model keep a design well inside it,
        # and a design it would refuse is refused here too rather than run for minutes.
        overrun = budget_overrun(spec)
        if overrun is not None:
            self.notify(f"{overrun[0].upper()}{overrun[1:]}: lower the samples or choose a model with fewer terms.",
                        title="Cannot design", severity="error")
            return
        self.query_one(ProgressBar).update(total=spec.starts, progress=0)
        self.query_one("#design-state", Static).update(f"running: 0 of {spec.starts} starts…")
        self.refresh_bindings()
        if self.designer is None:
            from jointid.studies.design_process import DesignProcess

            self.designer = DesignProcess()
        self.design(self.designer, spec)

    @work(thread=True, exclusive=True, group="design")
    def design(self, designer, spec) -> None:
        """Wait in a thread for the design process, reporting each start; the outcome is shown on the main thread."""
        from jointid.studies.design import DesignCancelled, DesignError
        from jointid.studies.design_process import DesignFailed

        worker = get_current_worker()

        def progress(done: int, total: int) -> None:  # a few times a second (design_process.PROGRESS_SECONDS)
            if not worker.is_cancelled:
                self.app.call_from_thread(self._progress, worker, done, total)

        try:
            # In this view's child process: a design in this thread would hold the GIL between its numpy
            # calls and delay the app's keys (benchmarks/bench_design.py, part 3).
            result = designer.run(spec, progress=progress, cancelled=lambda: worker.is_cancelled)
        except DesignCancelled:
            return
        except (DesignError, DesignFailed) as error:
            if not worker.is_cancelled:
                self.app.call_from_thread(self._failed, worker, str(error))
            return
        if not worker.is_cancelled:
            self.app.call_from_thread(self._deliver, worker, result)

    # The thread's calls run later on the app's loop: by then the view may have closed.

    def _progress(self, worker: Worker, done: int, total: int) -> None:
        if worker.is_cancelled:
            return
        with suppress(NoMatches):
            self.query_one(ProgressBar).update(total=total, progress=done)
            # One line of fixed size (views.tcss): no layout, only this line and the bar repaint.
            self.query_one("#design-state", Static).update(f"running: {done} of {total} starts…", layout=False)

    def _failed(self, worker: Worker, problem: str) -> None:
        if worker.is_cancelled:
            return
        with suppress(NoMatches):
            self.query_one("#design-state", Static).update("no design")
            self.notify(problem, title="No design", severity="error")

    def _deliver(self, worker: Worker, result) -> None:
        if worker.is_cancelled:
            return
        with suppress(NoMatches):
            self.show_result(result)

    @property
    def running(self) -> bool:
        """True while a design worker is still working."""
        return any(w.state in (WorkerState.PENDING, WorkerState.RUNNING)
                   for w in self.workers if w.group == "design")

    def show_result(self, result) -> None:
        """Display a finished design."""
        from jointid.present.design import active_sentence, design_table, design_verdict, limits_table

        self.result = result
        self.query_one("#design-state", Static).update(f"done: {result.converged} of {result.spec.starts} starts")
        self.query_one("#design-chart", SmallPlot).show(design_chart(result))
        self.query_one("#design-table", Static).update(design_table(result))
        self.query_one("#design-verdict", Static).update(design_verdict(result))
        self.query_one("#design-limits", Static).update(f"{limits_table(result)}\n{active_sentence(result)}")
        self.refresh_bindings()

    def on_worker_state_changed(self, event: Worker.StateChanged) -> None:
        """Update the keys that depend on a running design; say so when one was cancelled."""
        if event.worker.group != "design":
            return
        self.refresh_bindings()
        if event.state == WorkerState.CANCELLED and not self.running:
            with suppress(NoMatches):
                self.query_one("#design-state", Static).update("cancelled")

    def on_unmount(self) -> None:
        """Closing the view (or the app) ends its design process, running or not."""
        if self.designer is not None:
            self.designer.close()

    def check_action(self, action: str, parameters: tuple) -> bool | None:
        """Cancel only while a design runs; train and save only with a design to use (dimmed otherwise)."""
        if action == "cancel":
            return True if self.running else None
        if action in ("train", "save"):
            return True if self.result is not None else None
        return super().check_action(action, parameters)

    def action_cancel(self) -> bool:
        """Stop a running design; False when none was running."""
        if not self.running:
            return False
        self.workers.cancel_group(self, "design")
        self.designer.stop()  # at once, whatever the optimiser is doing
        self.query_one("#design-state", Static).update("cancelled")
        return True

    # --- using the design ---------------------------------------------------------------

    def action_train(self) -> None:
        """Train the explorer on the design (a fourth motion) and return to it."""
        if self.result is None:
            self.notify("Run a design first (g).", severity="warning")
            return
        self.on_train(self.result, self.limits, self.criterion)
        self.dismiss()

    def action_save(self) -> None:
        """Save the design as a motion file in the current folder, under a name not yet taken (in a browser: a
        download)."""
        if self.result is None:
            self.notify("Run a design first (g).", severity="warning")
            return
        from jointid.files import AlreadyExists, ExportError
        from jointid.synthetic.fourier import motion_text, save_motion

        if self.app.is_web:  # in a browser the file is a download, never the server's
            from ..web import deliver_motion

            name = f"jointid-design-{self.criterion}.json"
            deliver_motion(self.app, name, motion_text(self.result.motion))
            self.notify(f"Your browser downloads {name}: train on it with `jointid fit --motion-file {name}`.",
                        title="Saved")
            return

        for number in range(1, 1000):
            path = Path(f"jointid-design-{self.criterion}{'' if number == 1 else f'-{number}'}.json")
            try:
                save_motion(self.result.motion, path)
            except AlreadyExists:
                continue
            except ExportError as error:
                self.notify(str(error), title="Not saved", severity="error")
                return
            self.notify(f"Wrote {path}: train on it with `jointid fit --motion-file {path}`.", title="Saved")
            return
        self.notify("No free file name in the current folder.", title="Not saved", severity="error")

    def action_back(self) -> None:
        """Escape: cancel a running design, or return to the explorer when none runs."""
        if not self.action_cancel():
            self.dismiss()
