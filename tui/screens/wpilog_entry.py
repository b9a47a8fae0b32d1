"""The entry picker shown after a WPILib data log is chosen with Ctrl+O.

A SysId routine log needs no choice: it closes at once and the log opens as its
tests, runs of one joint. Any other log lists its numeric entries twice, first
for the angle (q), then for the effort (tau); when the angle entry's metadata
names no angle unit, a third list asks for it.
"""

from __future__ import annotations

import os

from textual import work
from textual.app import ComposeResult
from textual.containers import Vertical
from textual.widgets import Label, OptionList, Static
from textual.widgets.option_list import Option

from jointid.text_safety import shown_name

from ..widgets.footer import KeyFooter
from .picker import SurveyPicker

SYSID = "sysid"
"""The picker's result for a SysId routine log: open it as its tests."""

UNIT_CHOICES = ("radians", "rotations", "degrees")


class WpilogEntryScreen(SurveyPicker):
    """Picks the entries of a data log; dismisses with (SYSID,), (q entry, tau entry, unit or None) or None."""

    def __init__(self, path: str) -> None:
        """Create the picker of the data log (.wpilog) at `path`."""
        super().__init__(path)
        self.entries: list = []
        self.chosen: list[str] = []
        self.stage = "q"

    def compose(self) -> ComposeResult:
        """Heading, the entry list (filled once the log is surveyed), hint, keys."""
        with Vertical() as box:
            box.border_title = f"Choose the entries of {shown_name(os.path.basename(os.path.normpath(self.path)))}"
            yield Label("Reading the log's entries…", id="wpilog-status", markup=False)
            yield OptionList(id="wpilog-entries")
            yield Static("Up/Down choose, Enter takes it: the angle (q) first, then the effort (tau, a torque or "
                         "a voltage). A SysId routine log opens as its tests without asking. Escape cancels.",
                         markup=False)
        yield KeyFooter()

    @work(thread=True, exclusive=True, group="wpilog-survey")
    def survey(self) -> None:
        """Read every entry's name, type, count and unit."""
        from jointid.logs.table import LoadCancelled
        from jointid.logs.wpilog import wpilog_info

        def progress(done: int, total: int) -> None:
            self.app.call_from_thread(self.show_progress, min(done / max(total, 1), 1.0))

        try:
            info = wpilog_info(self.path, progress=progress, cancel=self.closed.is_set)
        except LoadCancelled:
            return
        except (ValueError, OSError) as error:  # LogError: one line
            self.app.call_from_thread(self.fail, str(error).splitlines()[0])
            return
        self.app.call_from_thread(self.show, info)

    def show_progress(self, share: float) -> None:
        """Say how much of a long log has been read."""
        if not self.chosen and self.stage == "q":
            self.query_one("#wpilog-status", Label).update(f"Reading the log's entries… {share:.0%}")

    def show(self, info) -> None:
        """Open a SysId routine log at once; otherwise list the numeric entries for the angle."""
        if len(info.routines) == 1:
            self.dismiss((SYSID,))
            return
        if info.lacking_voltage and not info.routines:
            self.fail(f"{self.path}: has SysId test-state entry sysid-test-state-{info.lacking_voltage[0]} but no "
                      "voltage entry: without the voltage there is no effort to fit")
            return
        self.entries = [entry for entry in info.entries if entry.numeric and entry.records]
        if len(self.entries) < 2:
            self.fail(f"{self.path}: has {len(self.entries)} numeric entr{'y' if len(self.entries) == 1 else 'ies'} "
                      "with records; a fit needs an angle and an effort")
            return
        self.list_entries("Choose the angle (q):")

    def list_entries(self, heading: str) -> None:
        """Fill the list with one line per numeric entry (the angle's left out when choosing the effort)."""
        from jointid.present.wpiloginfo import entry_line

        options = self.query_one(OptionList)
        options.clear_options()
        for entry in self.entries:
            if entry.name not in self.chosen:
                options.add_option(Option(entry_line(entry), id=entry.name))
        self.query_one("#wpilog-status", Label).update(heading)
        options.highlighted = 0
        options.focus()

    def on_option_list_option_selected(self, message: OptionList.OptionSelected) -> None:
        """Enter: take the angle, then the effort, then (if needed) the unit."""
        from jointid.logs.wpilog import angle_unit

        choice = message.option.id
        if self.stage == "unit":
            self.dismiss((*self.chosen, choice))
            return
        if choice in self.chosen:  # a key repeat after the list changed
            return
        self.chosen.append(choice)
        if self.stage == "q":
            self.stage = "tau"
            self.list_entries(f"Angle: {choice}. Choose the effort (tau):")
            return
        angle = next(entry for entry in self.entries if entry.name == self.chosen[0])
        if angle_unit(angle.unit)[0] is not None:
            self.dismiss((*self.chosen, None))
            return
        self.stage = "unit"
        options = self.query_one(OptionList)
        options.clear_options()
        for unit in UNIT_CHOICES:
            options.add_option(Option(unit, id=unit))
        self.query_one("#wpilog-status", Label).update(f"{angle.name} names no angle unit; choose it:")
        options.highlighted = 0
