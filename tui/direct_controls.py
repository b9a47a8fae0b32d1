"""Controls that act inside the key's own handler, so a choice and the new fit share one frame.

Textual's RadioSet and Button report a press by message. Each message is handled
one turn of the event loop later, and Textual paints in between: the pressed
button appeared in one frame, the fit a frame later and the released radio button
a frame after that, about 50 ms for one key where a frame is 16.7 ms. These
controls call the screen's action directly and show their state in place.
"""

from __future__ import annotations

from typing import Callable

from textual.binding import Binding
from textual.content import Content
from textual.widget import Widget
from textual.widgets import RadioButton, RadioSet


class ChoiceList(RadioSet):
    """A RadioSet that hands a chosen button's id straight to a callback.

    The owner shows the current choice with `show_pressed` (which sends no
    messages), so pressing, releasing and the owner's update happen together.
    """

    def __init__(self, *buttons: RadioButton, on_choose: Callable[[str], None], id: str | None = None) -> None:
        """Create the list.

        Args:
            buttons: The radio buttons, each with an id.
            on_choose: Called with the id of the button the user chose (Enter, Space or a click).
            id: Widget id.
        """
        super().__init__(*buttons, id=id)
        self._on_choose = on_choose

    def show_pressed(self, button_id: str) -> None:
        """Press the button with this id and release the others, now, without messages."""
        if self._pressed_button is not None and self._pressed_button.id == button_id:
            return
        buttons = list(self.query(RadioButton))
        with self.prevent(RadioButton.Changed):
            for button in buttons:
                button.value = button.id == button_id
        pressed = next(button for button in buttons if button.id == button_id)
        self._pressed_button = pressed
        self._selected = self._nodes.index(pressed)  # the highlight follows, as in RadioSet

    def action_toggle_button(self) -> None:
        """Enter or Space: choose the highlighted button."""
        if self._selected is not None:
            self._on_choose(self._nodes[self._selected].id)

    def _on_radio_button_changed(self, event: RadioButton.Changed) -> None:
        """A click toggled a button: choose it, or undo a click that would release the pressed one."""
        event.stop()
        if event.radio_button.value:
            self._on_choose(event.radio_button.id)
        else:
            with self.prevent(RadioButton.Changed):
                event.radio_button.value = True


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
        padding: 0 1;
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
        """The label."""
        return Content(self.label)

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
