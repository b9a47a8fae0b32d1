"""The Ctrl+O dialog: a path field, a folder tree, the log's role, what its effort is (a current's gear, torque
constant and efficiency), its angle's unit, zero and direction, all by keyboard: what `jointid --csv` takes as
--effort, --gear, --kt, --efficiency, --degrees, --zero and --clockwise, so a browser's user (`jointid serve`) can
read any log the command line can.

A ROS bag (a ROS 2 bag folder, or a .bag, .mcap or .db3 file) opens the joint
picker next; the request then names the joint and topic. A WPILib data log
(.wpilog) opens the entry picker, or, for a SysId routine log, loads its tests
as runs of one joint. The dialog stays open
while the chosen file loads (the progress dialog covers it): the explorer closes
it once the log is shown, and a file that cannot be used leaves it as it was,
path and options included, to correct or cancel.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Callable, Iterable

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical
from textual.screen import ModalScreen
from textual.widgets import DirectoryTree, Input, Label, RadioSet, Static

from jointid.cli.arguments import positive_number
from jointid.cli.effort_arguments import efficiency_number
from jointid.estimation.low_pass import FilterRequest
from jointid.logs.conventions import ZEROS, AngleConvention, EntryMap, LogConventions
from jointid.logs.effort import EffortReading
from jointid.logs.request import HELDOUT, RUN, TRAINING, LoadRequest
from jointid.options import DEFAULT_ORDER, DEFAULT_WINDOW
from jointid.text_safety import shown_name, typed_name

from ..widgets.footer import KeyFooter
from ..widgets.marks import ClearCheckbox, ClearRadioButton


class OptionError(ValueError):
    """A dialog option typed wrongly (a current's gear, kt or efficiency); the message is one line for a user."""


class LogTree(DirectoryTree):
    """The folder tree without hidden entries (`.git`, `.venv`), as file pickers show it; a hidden folder typed
    into the path field is still shown, with its contents. In a browser, nothing that resolves outside the
    server's data folder (a symlink out of it) is shown."""

    def __init__(self, path: str | Path, *, data_folder: Path | None = None, **kwargs) -> None:
        super().__init__(path, **kwargs)
        self.data_folder = data_folder

    def process_label(self, label):
        """A name as the tree shows it: escaped (text_safety.shown_name), since a file's name may hold bytes that
        are not UTF-8 or a terminal's control sequences."""
        return super().process_label(shown_name(label) if isinstance(label, str) else label)

    def filter_paths(self, paths: Iterable[Path]) -> Iterable[Path]:
        """Leave out names starting with a dot, and in a browser whatever lies outside the data folder."""
        shown = [path for path in paths if not path.name.startswith(".")]
        if self.data_folder is None:
            return shown
        from ..web import is_inside

        return [path for path in shown if is_inside(path, self.data_folder)]


class OpenLogScreen(ModalScreen[None]):
    """Choose a CSV log, a ROS bag or a WPILib data log: type a path and press Enter, or pick a file in the tree."""

    DEFAULT_CSS = """
    OpenLogScreen {
        align: center middle;
    }
    OpenLogScreen > Vertical {
        width: 90%;
        max-width: 100;
        height: 90%;
        border: round $primary;
        border-title-align: left;
        padding: 0 1;
    }
    OpenLogScreen Input {
        margin-bottom: 1;
    }
    OpenLogScreen #open-options {
        height: auto;
    }
    OpenLogScreen RadioSet {
        width: auto;
        height: auto;
        margin-right: 1;
    }
    OpenLogScreen RadioSet > ClearRadioButton {
        width: auto;
    }
    OpenLogScreen #open-checks {
        width: auto;
        height: auto;
    }
    OpenLogScreen ClearCheckbox {
        width: auto;
    }
    OpenLogScreen #open-current {
        height: 1;
    }
    OpenLogScreen #open-current > Label {
        width: auto;
        margin-right: 1;
    }
    OpenLogScreen #open-current > Input {
        width: 8;
        margin: 0 2 0 0;
    }
    OpenLogScreen DirectoryTree {
        height: 1fr;
        border: none;
    }
    OpenLogScreen .dialog--hint {
        height: auto;
        color: $text-muted;
    }
    """

    BINDINGS = [Binding("escape", "cancel", "Cancel", tooltip="Close without loading")]

    def __init__(self, folder: str | os.PathLike | None = None, *, data_folder: Path | None = None,
                 on_request: Callable[[LoadRequest, OpenLogScreen], None] | None = None,
                 heldout_allowed: bool = False,
                 run_allowed: bool = False,
                 derivatives: tuple[int | None, int] = (DEFAULT_WINDOW, DEFAULT_ORDER),
                 filtering: FilterRequest | None = None, conventions: LogConventions | None = None,
                 degrees: bool = False) -> None:
        """Create the dialog.

        Args:
            folder: Folder the tree starts in (default: the current directory).
            data_folder: In a browser, the only folder whose files may be opened (`jointid serve --data`);
                None in a terminal, where any path may.
            on_request: Called with the load request and this dialog when a file is chosen; the owner loads it
                and dismisses the dialog once it is shown (the dialog stays open if the file cannot be used).
                None dismisses the dialog with the request instead.
            heldout_allowed: True when a training log is loaded, so a held-out log can be chosen.
            run_allowed: True when a training log (or several runs) is loaded, so another run can be added.
            derivatives: Savitzky-Golay window and order for a log without qd or qdd
                (the explorer's --window and --order; a window of None is automatic).
            filtering: The parallel low-pass (the explorer's --cutoff and --decimate); None is automatic.
            conventions: The column map, angle convention and effort the fields start at (the explorer's
                --columns, --zero, --clockwise, --effort...; or the last log's); None is jointid's own.
            degrees: Whether Degrees starts ticked (the last log's angles were in degrees).
        """
        super().__init__()
        self.folder = Path(folder or os.getcwd())
        self.data_folder = data_folder
        self.on_request = on_request
        self.heldout_allowed = heldout_allowed
        self.run_allowed = run_allowed
        self.derivatives = derivatives
        self.filtering = FilterRequest() if filtering is None else filtering
        self.conventions = LogConventions() if conventions is None else conventions
        self.degrees = degrees

    def compose(self) -> ComposeResult:
        """Path field, role and degrees options, hint, folder tree, and the dialog's keys."""
        with Vertical() as box:
            box.border_title = "Open a joint log (CSV, ROS bag or WPILib .wpilog)"
            yield Label("Path (Enter opens it):")
            yield Input(value=f"{self.folder}{os.sep}", id="open-path", compact=True)
            session, angle = self.conventions.effort, self.conventions.angle
            kind = "torque" if session is None else session.kind
            with Horizontal(id="open-options"):
                with RadioSet(id="open-role", compact=True):
                    yield ClearRadioButton("Training log", value=True, id=f"role-{TRAINING}")
                    yield ClearRadioButton("Held-out log", id=f"role-{HELDOUT}",
                                      disabled=not self.heldout_allowed)
                    yield ClearRadioButton("Another run", id=f"role-{RUN}", disabled=not self.run_allowed)
                with RadioSet(id="open-effort", compact=True):
                    yield ClearRadioButton("Torque (N m)", value=kind == "torque", id="effort-torque")
                    yield ClearRadioButton("Voltage (V)", value=kind == "voltage", id="effort-voltage")
                    yield ClearRadioButton("Current (A)", value=kind == "current", id="effort-current")
                with RadioSet(id="open-zero", compact=True):  # the command line's --zero, word for word
                    for zero in ZEROS:
                        yield ClearRadioButton(f"Zero {zero}", value=angle.zero == zero, id=f"zero-{zero}")
                with Vertical(id="open-checks"):
                    yield ClearCheckbox("Degrees", self.degrees, id="open-degrees", compact=True)
                    yield ClearCheckbox("Clockwise", angle.clockwise, id="open-clockwise", compact=True)
            current = session if kind == "current" else None
            with Horizontal(id="open-current"):  # --gear, --kt, --efficiency: used for a current log only
                yield Label("Current: gear")
                yield Input("1" if current is None else f"{current.gear:g}", id="open-gear", compact=True,
                            disabled=current is None)
                yield Label("kt (N m/A)")
                yield Input("" if current is None else f"{current.kt:g}", placeholder="needed", id="open-kt",
                            compact=True, disabled=current is None)
                yield Label("efficiency")
                yield Input("1" if current is None else f"{current.efficiency:g}", id="open-efficiency",
                            compact=True, disabled=current is None)
            yield Static(
                "Tab moves between the fields and the tree (Enter opens a folder or loads a file). Zero: where "
                "the log's angle 0 points (a hanging pendulum's: down). Escape cancels."
                + (" Another run is pooled with the log shown (u: every run)."
                   if self.run_allowed else " A held-out log or another run needs a training log first.")
                + ("" if self.heldout_allowed or not self.run_allowed
                   else " With several runs each is predicted by the others: no held-out log."),
                classes="dialog--hint", markup=False,
            )
            yield LogTree(self.folder, data_folder=self.data_folder, id="open-tree")
        yield KeyFooter()  # the dialog's keys, over the explorer's

    def on_mount(self) -> None:
        """Start in the path field with the cursor at its end."""
        field = self.query_one("#open-path", Input)
        field.focus()
        field.cursor_position = len(field.value)

    def pressed(self, options: str, default: str) -> str:
        """The chosen option of a radio set (`open-role`...) without its id's prefix ('role-training' ->
        'training'), or `default` when none is pressed."""
        button = self.query_one(f"#{options}", RadioSet).pressed_button
        return default if button is None or button.id is None else button.id.split("-", 1)[1]

    def effort(self) -> EffortReading | None:
        """What the chosen effort measured (a current's gear, kt and efficiency as typed), or None for torque;
        OptionError naming a field typed wrongly."""
        kind = self.pressed("open-effort", "torque")
        if kind == "torque":
            return None
        if kind == "voltage":
            session = self.conventions.effort  # the command line's --effort-scale stays with a voltage log
            return session if session is not None and session.kind == "voltage" else EffortReading("voltage")
        gear = self.number("open-gear", "Gear", positive_number, default=1.0)
        kt = self.number("open-kt", "kt", positive_number)
        efficiency = self.number("open-efficiency", "Efficiency", efficiency_number, default=1.0)
        return EffortReading("current", 1.0, gear, kt, efficiency)

    def number(self, field: str, name: str, parse: Callable[[str], float], default: float | None = None) -> float:
        """A current option's typed value, read as the command line reads its flag; OptionError when it is not
        one (blank: `default`, or an error when there is none)."""
        import argparse

        text = self.query_one(f"#{field}", Input).value.strip()
        if not text and default is not None:
            return default
        if not text:
            raise OptionError(f"A current log needs {name}, the motor's torque constant in N m/A "
                              "(torque = gear x kt x efficiency x current).")
        try:
            return parse(text)
        except argparse.ArgumentTypeError as error:
            raise OptionError(f"{name} {error}.") from None

    def request(self, path: str, joint: str | None = None, topic: str | None = None, *, wpilog: bool = False,
                entries: EntryMap | None = None, units: str | None = None) -> LoadRequest:
        """The load request for a path (and a bag's joint and topic, or a data log's entries and unit) with the
        chosen role, effort, angle unit, zero and direction; OptionError when a current's value is typed
        wrongly."""
        role = self.pressed("open-role", TRAINING)
        window, order = self.derivatives
        degrees = self.query_one("#open-degrees", ClearCheckbox).value
        fields = self.conventions.request_fields(bag=joint is not None or wpilog)
        fields["angle"] = AngleConvention(self.pressed("open-zero", "right"),
                                          self.query_one("#open-clockwise", ClearCheckbox).value)
        effort = self.effort()
        if effort is None:
            fields.pop("effort", None)
        else:
            fields["effort"] = effort
        return LoadRequest(os.path.expanduser(path.strip()), role, degrees, window=window, order=order,
                           joint=joint, topic=topic, filtering=self.filtering, **fields,
                           wpilog=wpilog, entries=entries, units=units)

    def on_radio_set_changed(self, event: RadioSet.Changed) -> None:
        """A current's gear, kt and efficiency can be typed only while Current is chosen."""
        if event.radio_set.id == "open-effort":
            for field in self.query("#open-current Input"):
                field.disabled = event.pressed.id != "effort-current"

    def submit(self, request: LoadRequest) -> None:
        """Hand a request to the owner, which closes this dialog once the log is shown."""
        if self.on_request is None:
            self.dismiss(request)
        else:
            self.on_request(request, self)

    def within_data_folder(self, path: str) -> str | None:
        """The path to use: as it is in a terminal; in a browser resolved inside the data folder, or None (after
        saying why) when it lies outside."""
        if self.data_folder is None:
            return path
        from ..web import OutsideDataFolder, inside

        try:
            return inside(path, self.data_folder)
        except OutsideDataFolder as error:
            self.notify(str(error), title="No file chosen", severity="warning")
            return None

    def choose(self, path: str) -> None:
        """Load a CSV log now; for a bag, pick its joint first (the dialog stays open behind the picker)."""
        from jointid.logs.bag import looks_like_bag
        from jointid.logs.wpilog import looks_like_wpilog

        path = self.within_data_folder(path)
        if path is None:
            return
        try:
            self.request(path)  # the options' typed values are checked before any picker opens
        except OptionError as error:
            self.notify(str(error), title="No file chosen", severity="warning")
            return
        if os.path.basename(path) == "metadata.yaml":  # chosen inside a ROS 2 bag folder: the folder is the bag
            path = os.path.dirname(path)
        if looks_like_wpilog(path):
            self.choose_entries(path)
            return
        if not looks_like_bag(path):
            self.submit(self.request(path))
            return
        from .bag_joint import BagJointScreen

        def picked(choice: tuple[str, str] | None) -> None:
            if choice is not None:
                self.submit(self.request(path, *choice))

        self.app.push_screen(BagJointScreen(path), picked)

    def choose_entries(self, path: str) -> None:
        """A WPILib data log: a SysId routine log loads as its tests, any other after its entries are picked."""
        from .wpilog_entry import SYSID, WpilogEntryScreen

        def picked(choice: tuple | None) -> None:
            if choice is None:
                return
            if choice[0] == SYSID:
                self.submit(self.request(path, wpilog=True))
                return
            angle, effort, unit = choice
            self.submit(self.request(path, wpilog=True, entries=EntryMap((("q", angle), ("tau", effort))),
                                     units=unit))

        self.app.push_screen(WpilogEntryScreen(path), picked)

    def existing(self, typed: str) -> str:
        """The path typed, or the name it shows escaped (text_safety.typed_name: `caf\\xe9.csv` for a name whose
        bytes are not UTF-8) when only that exists."""
        base = "" if self.data_folder is None else self.data_folder  # in a browser relative paths start there
        for candidate in (typed, typed_name(typed)):
            if os.path.lexists(os.path.join(base, candidate)):
                return candidate
        return typed

    def on_input_submitted(self, message: Input.Submitted) -> None:
        """Enter in the path field (or a current's field): a folder opens in the tree, a file is loaded; nothing or
        a typo stays here."""
        path = self.existing(os.path.expanduser(self.query_one("#open-path", Input).value.strip()))
        if not path:
            self.notify("Type the path of a CSV log or ROS bag, or choose one in the folder tree.",
                        title="No file chosen", severity="warning")
            return
        if self.data_folder is not None:  # in a browser relative paths start in the data folder, and stay in it
            path = self.within_data_folder(path)
            if path is None:
                return
        if os.path.isdir(path) and not os.path.exists(os.path.join(path, "metadata.yaml")):
            self.query_one(DirectoryTree).path = path
            return
        if not os.path.lexists(path):  # say so here, where the path can still be corrected
            self.notify(f"{shown_name(path)}: no such file", title="No file chosen", severity="warning")
            return
        self.choose(path)

    def on_directory_tree_file_selected(self, message: DirectoryTree.FileSelected) -> None:
        """A file chosen in the tree is loaded (a bag's after its joint is picked); the path field shows it, so a
        file that cannot be used is named there to correct."""
        field = self.query_one("#open-path", Input)
        field.value = shown_name(str(message.path))
        field.cursor_position = len(field.value)
        self.choose(str(message.path))

    def action_cancel(self) -> None:
        """Close without loading."""
        self.dismiss(None)
