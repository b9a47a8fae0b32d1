"""The main screen's log mode: open a log in a worker, show it in place of the synthetic experiment, export."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

from textual import work
from textual.content import Content
from textual.widgets import Input, Static

from jointid.report import fit_document, readouts

from .charts import TorqueChart
from .direct_controls import ChoiceList
from .fitting import FittingLine
from .precision import precision
from .readouts import ReadoutPanel
from .stepper import Stepper

# The log reader, file dialog, progress dialog and export are imported when first used:
# the explorer's first frame needs none of them (about 15 ms of start-up).
if TYPE_CHECKING:
    from .loading import LoadingScreen
    from .log_source import LoadedLogs, LoadRequest

FROM_LOG = "from log"
"""Text of the noise, samples and seed fields while a log is shown."""


COMPACT_LOG_NOTE = "From log: c or 1/2/3 for synthetic"
"""The note on small terminals, one line (the help gives the rest)."""


def log_note(logs: LoadedLogs, compact: bool = False) -> str:
    """Why the synthetic controls are off, and how to get them back (one short line when compact)."""
    if compact:
        return COMPACT_LOG_NOTE
    heldout = f", held-out {os.path.basename(logs.heldout.path)}" if logs.heldout is not None else ""
    return (f"From log: {logs.name}{heldout}, {logs.result.training.count} samples fitted; "
            "noise, samples and seed do not apply. 1/2/3 or c: back to synthetic.")


class LogMode:
    """Log actions and the log push-down for MainScreen, which owns the `logs` reactive."""

    def watch_logs(self, logs: LoadedLogs | None) -> None:
        """Show the loaded logs' fit, or go back to the synthetic experiment (the log's one watcher)."""
        self.set_class(logs is not None, "-log")
        self.set_class(logs is not None and logs.heldout is None, "-no-heldout")
        self.refresh_bindings()  # Close log appears or goes
        self.query_one("#motion", ChoiceList).set_option(
            "motion-log", label=None if logs is None else f"Log: {logs.name}", shown=logs is not None)
        for stepper in self.query(Stepper):
            stepper.disabled = logs is not None
        if logs is None:
            self.watch_settings(self.compute_settings())
            return
        from .log_source import log_heldout_chart, log_training_chart

        self.result = logs.result
        self.query_one("#motion", ChoiceList).show_pressed("motion-log")
        for stepper in self.query(Stepper):
            with stepper.prevent(Input.Changed):
                stepper.value = FROM_LOG
        self.show_log_note()
        columns = max(self.app.size.width, 80)  # a chart is never wider than the terminal
        self.query_one("#training-chart", TorqueChart).show(log_training_chart(logs, columns))
        heldout = log_heldout_chart(logs, columns)
        if heldout is not None:
            self.query_one("#heldout-chart", TorqueChart).show(heldout)
        self.query_one(ReadoutPanel).show(readouts(logs.result), precision(logs.result))
        status = " ".join((logs.result.message, *(n if n.endswith(".") else f"{n}." for n in logs.notes())))
        self.query_one("#status", FittingLine).show((Content(status),))

    def show_log_note(self) -> None:
        """The note on the off controls, one line on compact screens (80x24 has no room for more)."""
        if self.logs is not None:
            self.query_one("#log-note", Static).update(log_note(self.logs, self.has_class("-compact")))

    def check_action(self, action: str, parameters: tuple) -> bool | None:
        """Close log exists only while a log is shown (hidden from the footer otherwise)."""
        if action == "close_log":
            return self.logs is not None
        return super().check_action(action, parameters)

    def close_log(self) -> None:
        """Leave log mode; the synthetic settings are shown again as they were."""
        self.logs = None

    def action_close_log(self) -> None:
        """Return from the log to the synthetic experiment."""
        if self.logs is None:
            self.notify("No log is loaded.", severity="warning")
        self.close_log()

    def needs_synthetic(self, view: str) -> bool:
        """True (after saying why) when a view of synthetic settings is asked for while a log is shown."""
        if self.logs is None:
            return False
        self.notify(f"{view} needs a synthetic experiment: press 1, 2, 3 or c to leave the log.",
                    severity="warning")
        return True

    def action_open_log(self) -> None:
        """Choose a training or held-out log to load."""
        from .file_dialog import OpenLogScreen

        folder = os.path.dirname(os.path.abspath(self.logs.training.path)) if self.logs else None
        self.app.push_screen(OpenLogScreen(folder, heldout_allowed=self.logs is not None,
                                           derivatives=self.app.derivatives), self.start_loading)

    def start_loading(self, request: LoadRequest | None) -> None:
        """Load a chosen file in a worker behind a progress dialog."""
        if request is None:
            return
        from .loading import LoadingScreen

        dialog = LoadingScreen(request.path)
        self.app.push_screen(dialog)
        self.load_worker(request, self.logs, dialog)

    @work(thread=True, exclusive=True, group="log-load")
    def load_worker(self, request: LoadRequest, current: LoadedLogs | None, dialog: LoadingScreen) -> None:
        """Read and fit the log off the main thread; the outcome is applied on the main thread."""
        from jointid.csvlog import LoadCancelled

        from .log_source import load_request

        app = self.app
        try:
            logs = load_request(request, current, lambda done, total: app.call_from_thread(dialog.advance, done, total),
                                dialog.cancelled.is_set)
        except LoadCancelled:
            app.call_from_thread(self.finish_loading, dialog, None, "Loading cancelled; nothing changed.")
        except (ValueError, OSError) as error:  # LogError is a ValueError with a one-line text
            app.call_from_thread(self.finish_loading, dialog, None, str(error).splitlines()[0])
        else:
            app.call_from_thread(self.finish_loading, dialog, logs, None)

    def finish_loading(self, dialog: LoadingScreen, logs: LoadedLogs | None, problem: str | None) -> None:
        """Close the progress dialog and show the new logs, or say why the current data stay."""
        if dialog.is_attached:
            dialog.dismiss()
        if logs is None:
            cancelled = dialog.cancelled.is_set()
            self.notify(problem, title="Log not loaded", severity="warning" if cancelled else "error")
            return
        self.logs = logs
        loaded = logs.heldout if logs.heldout is not None and logs.heldout.path == dialog.path else logs.training
        self.notify(loaded.source_text(), title="Held-out log loaded" if loaded is logs.heldout else "Log loaded")

    def export_content(self) -> tuple[str, dict]:
        """File stem and JSON document of the current result, as `jointid fit [--csv] --json` prints it."""
        if self.logs is not None:
            return f"{Path(self.logs.training.path).stem}-fit", self.logs.document()
        s = self.compute_settings()
        return (f"jointid-{s.motion}-{s.noise:.2f}-{s.samples}-{s.seed}",
                fit_document(self.result, settings=vars(s).copy()))

    def action_export(self) -> None:
        """Export the fit as JSON and the screen as SVG into a chosen folder."""
        from .export import ExportScreen

        svg = self.app.export_screenshot()  # before the dialog covers the screen
        stem, document = self.export_content()
        self.app.push_screen(ExportScreen(stem), lambda folder: self.write_export(folder, stem, document, svg))

    def write_export(self, folder: str | None, stem: str, document: dict, svg: str) -> None:
        """Write the export pair and say where, or say why not."""
        if folder is None:
            return
        from jointid.export import ExportError

        from .export import write_export

        try:
            json_path, svg_path = write_export(folder, stem, document, svg)
        except ExportError as error:
            self.notify(str(error), title="Nothing exported", severity="error")
            return
        self.notify(f"Wrote {json_path} and {svg_path}", title="Exported")
