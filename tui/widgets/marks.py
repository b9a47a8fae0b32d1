"""Toggle buttons whose state reads without colour: the mark is empty when off (NO_COLOR, 256 colours)."""

from __future__ import annotations

from textual.widgets import Checkbox, RadioButton


class ClearMark:
    """Mixin for a Textual toggle button: its mark shows only when it is on."""

    ON_MARK = "●"
    """The mark shown inside the button when on."""

    @property
    def BUTTON_INNER(self) -> str:  # noqa: N802 - overrides Textual's class constant
        """The mark inside the button: ON_MARK when on, blank when off."""
        return self.ON_MARK if self.value else " "


class ClearRadioButton(ClearMark, RadioButton):
    """A radio button whose mark is empty when off, so the choice reads without colour."""


class ClearCheckbox(ClearMark, Checkbox):
    """A checkbox whose X shows only when it is ticked."""

    ON_MARK = "X"
