"""The joint picker shown after a ROS bag is chosen with Ctrl+O: every joint of its JointState topics."""

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

SURVEY_MESSAGES = 2000
"""Messages read per JointState topic to list its joints: enough to see every joint, quick on a huge bag."""


class BagJointScreen(SurveyPicker):
    """Lists the joints of a bag's JointState topics with their filled fields; Enter picks (joint, topic)."""

    def __init__(self, path: str) -> None:
        """Create the picker of the bag at `path` (a ROS 2 folder, .bag, .mcap or .db3)."""
        super().__init__(path)
        self.choices: list[tuple[str, str]] = []

    def compose(self) -> ComposeResult:
        """Heading, the joint list (filled once the bag is surveyed), hint, keys."""
        with Vertical() as box:
            box.border_title = f"Choose a joint of {shown_name(os.path.basename(os.path.normpath(self.path)))}"
            yield Label("Reading the bag's JointState topics…", id="bag-status", markup=False)
            yield OptionList(id="bag-joints")
            yield Static("Up/Down choose a joint, Enter loads it (q from position, tau from effort, qd from "
                         "velocity when filled). Escape cancels.", markup=False)
        yield KeyFooter()

    @work(thread=True, exclusive=True, group="bag-survey")
    def survey(self) -> None:
        """List joints from the first SURVEY_MESSAGES messages of each JointState topic."""
        from jointid.logs.bag import bag_info

        try:
            info = bag_info(self.path, limit=SURVEY_MESSAGES)
        except (ValueError, OSError) as error:  # LogError: one line
            self.app.call_from_thread(self.fail, str(error).splitlines()[0])
            return
        self.app.call_from_thread(self.show, info)

    def show(self, info) -> None:
        """Fill the list with one line per joint and topic."""
        from jointid.present.baginfo import joint_line

        if not info.joint_states:
            self.fail(f"{self.path}: no sensor_msgs/JointState topic; nothing to fit")
            return
        options = self.query_one(OptionList)
        for topic in info.joint_states:
            for joint in topic.joints:
                self.choices.append((joint.name, topic.name))
                prefix = f"{topic.name}  " if len(info.joint_states) > 1 else ""
                options.add_option(Option(prefix + joint_line(joint)))
        surveyed = min(t.messages for t in info.joint_states)
        self.query_one("#bag-status", Label).update(
            f"{info.kind} bag, {info.duration:.6g} s; joints seen in the first {surveyed} messages:")
        options.highlighted = 0
        options.focus()

    def on_option_list_option_selected(self, message: OptionList.OptionSelected) -> None:
        """Enter on a joint: load it."""
        self.dismiss(self.choices[message.option_index])
