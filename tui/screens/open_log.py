"""The Ctrl+O dialog: a path field, a folder tree, the log's role, what its effort is and its angle unit, all by
keyboard.

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

from jointid.estimation.low_pass import FilterRequest
from jointid.logs.conventions import EntryMap, LogConventions
from jointid.logs.effort import EffortReading
from jointid.logs.request import HELDOUT, RUN, TRAINING, LoadRequest
from jointid.options import DEFAULT_ORDER, DEFAULT_WINDOW
from jointid.text_safety import shown_name, typed_name

from ..widgets.footer import KeyFooter
from ..widgets.marks import ClearCheckbox, ClearRadioButton


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
        width: 20;
        height: auto;
        margin-right: 2;
    }
    OpenLogScreen RadioSet > ClearRadioButton {
        width: 20;
    }
    OpenLogScreen ClearCheckbox {
        width: auto;
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
                 filtering: FilterRequest | None = None, conventions: LogConventions | None = None) -> None:
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
            conventions: The column map and angle convention (the explorer's --columns, --zero and
                --clockwise); None is jointid's own.
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

    def compose(self) -> ComposeResult:
        """Path field, role and degrees options, hint, folder tree, and the dialog's keys."""
        with Vertical() as box:
            box.border_title = "Open a joint log (CSV, ROS bag or WPILib .wpilog)"
            yield Label("Path (Enter opens it):")
            yield Input(value=f"{self.folder}{os.sep}", id="open-path", compact=True)
            with Horizontal(id="open-options"):
                with RadioSet(id="open-role", compact=True):
                    yield ClearRadioButton("Training log", value=True, id=f"role-{TRAINING}")
                    yield ClearRadioButton("Held-out log", id=f"role-{HELDOUT}",
                                      disabled=not self.heldout_allowed)
                    yield ClearRadioButton("Another run", id=f"role-{RUN}", disabled=not self.run_allowed)
                session = self.conventions.effort
                kind = "torque" if session is None else session.kind
                with RadioSet(id="open-effort", compact=True):
                    yield ClearRadioButton("Torque (N m)", value=kind == "torque", id="effort-torque")
                    yield ClearRadioButton("Voltage (V)", value=kind == "voltage", id="effort-voltage")
                    # A current needs its gear and kt, which only the command line gives (--effort current).
                    yield ClearRadioButton("Current (A)", value=kind == "current", id="effort-current",
                                           disabled=kind != "current")
                yield ClearCheckbox("Angles in degrees", id="open-degrees", compact=True)
            yield Static(
                "Tab moves between the path, the options and the tree; in the tree Enter opens "
                "a folder or loads a file. A ROS bag (its folder's path, or a .bag, .mcap or .db3 file) "
                "asks for a joint next, a WPILib .wpilog for its entries (a SysId log opens as its tests). "
                "A voltage log is fitted in volts (WPILib's gains; g shows them). "
                "Escape cancels."
                + (" Another run is fitted alone, then pooled with the log shown (u: every run)."
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

    def request(self, path: str, joint: str | None = None, topic: str | None = None, *, wpilog: bool = False,
                entries: EntryMap | None = None, units: str | None = None) -> LoadRequest:
        """The load request for a path (and a bag's joint and topic, or a data log's entries and unit) with the
        chosen role and unit."""
        pressed = self.query_one("#open-role", RadioSet).pressed_button
        roles = {f"role-{role}": role for role in (TRAINING, HELDOUT, RUN)}
        role = TRAINING if pressed is None else roles.get(pressed.id, TRAINING)
        window, order = self.derivatives
        degrees = self.query_one("#open-degrees", ClearCheckbox).value
        fields = self.conventions.request_fields(bag=joint is not None or wpilog)
        effort = self.query_one("#open-effort", RadioSet).pressed_button
        if effort is not None and effort.id == "effort-voltage":
            fields["effort"] = EffortReading("voltage")
        elif effort is not None and effort.id == "effort-torque":
            fields.pop("effort", None)
        return LoadRequest(os.path.expanduser(path.strip()), role, degrees, window=window, order=order,
                           joint=joint, topic=topic, filtering=self.filtering, **fields,
                           wpilog=wpilog, entries=entries, units=units)

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
        """Enter in the path field: a folder opens in the tree, a file is loaded; nothing or a typo stays here."""
        path = self.existing(os.path.expanduser(message.value.strip()))
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
