"""Controls that act inside the key's own handler, so a choice and the new fit share one frame.

Textual's RadioSet and Button report a press by message. Each message is handled
one turn of the event loop later, and Textual paints in between: the pressed
button appeared in one frame, the fit a frame later and the released radio button
a frame after that, about 50 ms for one key where a frame is 16.7 ms. These
controls call the screen's action directly and show their state in place.
"""

from __future__ import annotations

from typing import Callable

from textual import events
from textual.binding import Binding
from textual.content import Content
from textual.style import Style
from textual.widget import Widget


class ChoiceList(Widget, can_focus=True):
    """A radio list drawn by one widget, that hands a chosen option's id straight to a callback.

    Looks and keys as Textual's compact RadioSet (Up/Down move the highlight,
    Enter or Space choose, a click chooses the line), but it is one widget
    instead of one per option, without RadioSet's and ToggleButton's 24 style
    rules, and the owner shows the current choice with `show_pressed`, which
    sends no messages. An option can be hidden (the log's entry, while no log is shown).
    """

    DEFAULT_CSS = """
    ChoiceList {
        height: auto;
        width: 1fr;
        background: $surface;
        pointer: pointer;
        &:focus {
            background-tint: $foreground 5%;
        }
        & > .choice-list--button {
            color: $panel-darken-2;
            background: $panel;
        }
        & > .choice-list--button-on {
            color: $text-success;
            background: $panel;
        }
        & > .choice-list--highlight {
            background: $block-cursor-blurred-background;
        }
        &:focus > .choice-list--highlight {
            color: $block-cursor-foreground;
            background: $block-cursor-background;
            text-style: $block-cursor-text-style;
        }
    }
    """

    COMPONENT_CLASSES = {"choice-list--button", "choice-list--button-on", "choice-list--highlight"}

    BINDINGS = [
        Binding("down,right", "move(1)", "Next option", show=False),
        Binding("up,left", "move(-1)", "Previous option", show=False),
        Binding("enter,space", "choose", "Choose", show=False),
    ]

    ON_MARK = "●"
    """The mark inside the pressed option's button; the others are blank, so it reads without colour."""

    def __init__(self, options: list[tuple[str, str]], *, on_choose: Callable[[str], None],
                 hidden: tuple[str, ...] = (), id: str | None = None) -> None:
        """Create the list.

        Args:
            options: (id, label) of each option, in order.
            on_choose: Called with the id of the option the user chose.
            hidden: Ids of options not shown for now.
            id: Widget id.
        """
        super().__init__(id=id)
        self.labels = dict(options)
        self.hidden = set(hidden)
        self.pressed: str | None = None
        self.highlighted: str = options[0][0]
        self._on_choose = on_choose

    @property
    def shown(self) -> list[str]:
        """Ids of the options on screen, in order."""
        return [option for option in self.labels if option not in self.hidden]

    def show_pressed(self, option: str) -> None:
        """Press this option and move the highlight to it, without messages."""
        if option != self.pressed:
            self.pressed = self.highlighted = option
            self.refresh()

    def set_option(self, option: str, label: str | None = None, shown: bool | None = None) -> None:
        """Relabel an option, or show or hide it (a relayout only when that changes anything)."""
        before = (self.labels.get(option), option in self.hidden)
        if label is not None:
            self.labels[option] = label
        if shown:
            self.hidden.discard(option)
        elif shown is not None:
            self.hidden.add(option)
        if (self.labels.get(option), option in self.hidden) != before:
            self.refresh(layout=True)

    def action_move(self, step: int) -> None:
        """Move the highlight to the next or previous option shown, wrapping around."""
        shown = self.shown
        index = shown.index(self.highlighted) if self.highlighted in shown else 0
        self.highlighted = shown[(index + step) % len(shown)]
        self.refresh()

    def action_choose(self) -> None:
        """Enter or Space: choose the highlighted option."""
        self._on_choose(self.highlighted)

    def on_click(self, event: events.Click) -> None:
        """A click chooses the option on its line."""
        shown = self.shown
        if 0 <= event.y < len(shown):
            self.highlighted = shown[event.y]
            self.refresh()
            self._on_choose(self.highlighted)

    def get_content_height(self, container, viewport, width: int) -> int:
        """One line per option shown."""
        return len(self.shown)

    def render(self) -> Content:
        """Each option as a radio button and its label; the highlighted label as a cursor."""
        side = Style(foreground=self.get_visual_style("choice-list--button").background,
                     background=self.background_colors[1])
        lines = []
        for option in self.shown:
            on = option == self.pressed
            button = self.get_visual_style("choice-list--button-on" if on else "choice-list--button")
            label = Content(f" {self.labels[option]} ")
            if option == self.highlighted:
                label = label.stylize_before(self.get_visual_style("choice-list--highlight"))
            lines.append(Content.assemble(("▐", side), (self.ON_MARK if on else " ", button), ("▌", side)) + label)
        return Content("\n").join(lines)


class ActionButton(Widget, can_focus=True):
    """A one-line button that calls its callback when pressed (Enter, Space or a click).

    Drawn like Textual's compact Button (bold on the surface colour, reversed
    when focused, dimmed for a moment when pressed), without Button's 57 style
    rules, which every widget of the screen was matched against at start-up.
    """

    DEFAULT_CSS = """
    ActionButton {
        width: auto;
        height: 1;
        content-align: center middle;
        text-style: bold;
        color: $button-foreground;
        background: $surface;
        &:focus {
            text-style: $button-focus-text-style;
            background-tint: $foreground 5%;
        }
        &:hover {
            background: $surface-darken-1;
        }
        &.-active {
            tint: $background 30%;
        }
    }
    """

    BINDINGS = [Binding("enter,space", "press", "Press", show=False)]

    ACTIVE_EFFECT_DURATION = 0.2
    """Seconds the button looks pressed after a press."""

    def __init__(self, label: str, *, on_press: Callable[[], None], id: str | None = None) -> None:
        """Create the button.

        Args:
            label: The button's text.
            on_press: Called when the button is pressed.
            id: Widget id.
        """
        super().__init__(id=id)
        self.label = label
        self._on_press = on_press

    def render(self) -> Content:
        """The label with a space each side (inside the focus highlight, as Button draws it)."""
        return Content(f" {self.label} ")

    def on_click(self) -> None:
        """A click presses the button."""
        self.press()

    def action_press(self) -> None:
        """Enter or Space presses the button."""
        self.press()

    def press(self) -> None:
        """Look pressed for a moment and run the callback in this same handler."""
        if self.disabled or not self.display:
            return
        self.add_class("-active")
        self.set_timer(self.ACTIVE_EFFECT_DURATION, lambda: self.remove_class("-active"))
        self._on_press()
