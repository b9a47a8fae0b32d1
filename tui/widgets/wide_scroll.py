"""A sideways scroll for a table or a code line kept whole on a narrow screen, with keys that reach its far end."""

from __future__ import annotations

from typing import ClassVar

from textual.binding import Binding, BindingType
from textual.containers import HorizontalScroll


class WideScroll(HorizontalScroll):
    """HorizontalScroll whose End, Home and Shift+arrows move sideways: its Right moves one column, so the end of a
    190-column constructor line at 80 columns was a hundred presses away (End scrolled down, not right)."""

    BINDINGS: ClassVar[list[BindingType]] = [
        Binding("end", "scroll_to_right_end", "Right end", show=False),
        Binding("home", "scroll_to_left_end", "Left end", show=False),
        Binding("shift+right", "page_right", "Page right", show=False),
        Binding("shift+left", "page_left", "Page left", show=False),
    ]

    def action_scroll_to_right_end(self) -> None:
        self.scroll_to(x=self.max_scroll_x, animate=False)

    def action_scroll_to_left_end(self) -> None:
        self.scroll_to(x=0, animate=False)
