"""The key footer, built only when the keys it shows change."""

from __future__ import annotations

from textual.screen import Screen
from textual.widgets import Footer


class KeyFooter(Footer):
    """Textual's footer, always compact, rebuilt only when the keys it would show change.

    Textual rebuilds the footer on every bindings signal (each focus change, each
    screen resume), and a compact switch restyles every key twice; at start-up
    that was about 100 ms of identical rebuilds before the first complete frame.
    """

    def __init__(self) -> None:
        """Create a compact footer."""
        super().__init__(compact=True)
        self._shown: tuple | None = None

    def bindings_changed(self, screen: Screen) -> None:
        """Rebuild only if the keys, their descriptions or their enabled state differ from the shown ones."""
        if screen.app.app_focus and screen is self.screen:
            shown = tuple(
                (binding.key, binding.description, binding.group, enabled)
                for _, binding, enabled, _ in screen.active_bindings.values()
                if binding.show
            )
            if shown == self._shown and self._bindings_ready:
                return
            self._shown = shown
        super().bindings_changed(screen)
