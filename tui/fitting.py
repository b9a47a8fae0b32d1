"""A one-line text that picks the longest of its variants that fits the width."""

from __future__ import annotations

from textual.content import Content
from textual.widget import Widget


class FittingLine(Widget):
    """One line of text with shorter variants for narrow terminals.

    The longest variant that fits the current width is shown; when none fits,
    the shortest one wraps rather than being cut off.
    """

    DEFAULT_CSS = """
    FittingLine {
        height: auto;
    }
    """

    def __init__(self, *, classes: str | None = None) -> None:
        """Create an empty line.

        Args:
            classes: CSS classes.
        """
        super().__init__(classes=classes)
        self.variants: tuple[Content, ...] = (Content(""),)

    def show(self, variants: tuple[Content, ...]) -> None:
        """Display new variants, longest first."""
        if variants != self.variants:
            self.variants = variants
            self.refresh(layout=True)

    def pick(self, width: int) -> Content:
        """The variant shown at a given width."""
        for variant in self.variants:
            if variant.cell_length <= width:
                return variant
        return self.variants[-1]

    @property
    def shown(self) -> Content:
        """The variant shown at the current width."""
        return self.pick(self.content_region.width or self.size.width)

    def render(self) -> Content:
        """The chosen variant."""
        return self.shown
