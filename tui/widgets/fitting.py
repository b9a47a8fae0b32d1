"""Text that picks the longest of its variants that fits the width (or its reserved rows), and wraps the last resort."""

from __future__ import annotations

from textual.content import Content

from .rows import RowStrips


class FittingLine(RowStrips):
    """One line of text with shorter variants for narrow terminals.

    The longest variant that fits the current width is shown (with `min_lines`
    above 1, the first that wraps into that many rows); when none fits, the
    shortest one wraps rather than being cut off. `min_lines` rows are
    always taken, so texts of up to that many lines keep the widget's height
    and a new text repaints only this widget instead of relayouting the screen.
    """

    DEFAULT_CSS = """
    FittingLine {
        height: auto;
    }
    """

    def __init__(self, *, id: str | None = None, classes: str | None = None, min_lines: int = 1) -> None:
        """Create an empty line.

        Args:
            id: Widget id.
            classes: CSS classes.
            min_lines: Rows reserved whatever the text (blank below a shorter one).
        """
        super().__init__(id=id, classes=classes)
        self.variants: tuple[Content, ...] = (Content(""),)
        self.sizing: tuple[Content, ...] = self.variants
        """For each variant, the text whose fit decides whether it is shown (see `show`)."""
        self.min_lines = min_lines
        self._heights: dict[int, int] = {}
        """Rows at each width asked for, for the shown variants (wrapping a long text costs ~50 µs)."""
        self._picked: dict[int, Content] = {}
        """The variant shown at each width asked for (choosing by rows wraps the variants)."""

    def show(self, variants: tuple[Content, ...], sizing: tuple[Content, ...] | None = None) -> None:
        """Display new variants, longest first.

        Args:
            variants: The texts, longest first.
            sizing: For each variant, the text whose fit decides whether it is shown (the variant itself by
                default): a title whose count grows ("1000 seeds") is chosen by its widest form, so the choice
                depends on the width alone and does not flip as the count widens.
        """
        sizing = variants if sizing is None else sizing
        if (variants, sizing) == (self.variants, self.sizing):
            return
        width = self.content_region.width
        old_height = self.height_at(width)
        self.variants, self.sizing = variants, sizing
        self._heights, self._picked = {}, {}
        # A relayout of the whole screen costs more than the rest of a key press; only ask
        # for one when this widget's height really changed.
        if not width or self.height_at(width) != old_height:
            self.refresh(layout=True)
        else:
            self.refresh_rows()

    def set_min_lines(self, min_lines: int) -> None:
        """Reserve another number of rows (a relayout only when that changes the height)."""
        if min_lines != self.min_lines:
            width = self.content_region.width
            old_height = self.height_at(width)
            self.min_lines, self._heights, self._picked = min_lines, {}, {}
            if not width or self.height_at(width) != old_height:
                self.refresh(layout=True)

    def line_count(self, width: int) -> int:
        """Lines the shown variant takes at a given width."""
        if width <= 0:
            return 1
        variant = self.pick(width)
        if variant.cell_length <= width and "\n" not in variant.plain:
            return 1  # fits on one line: no need to wrap it (the status sentence's wrap is 0.1 ms)
        return len(variant.wrap(width))

    def height_at(self, width: int) -> int:
        """Rows taken at a given width: the text's lines, at least `min_lines`."""
        height = self._heights.get(width)
        if height is None:
            height = self._heights[width] = max(self.line_count(width), self.min_lines)
        return height

    def get_content_height(self, container, viewport, width: int) -> int:
        """The text's lines at this width, at least `min_lines`."""
        return self.height_at(width)

    def pick(self, width: int) -> Content:
        """The variant shown at a given width: the first that fits in `min_lines` rows, else the last."""
        picked = self._picked.get(width)
        if picked is None:
            picked = self.variants[-1]
            for variant, sizing in zip(self.variants, self.sizing):
                if sizing.cell_length <= width or (
                        self.min_lines > 1 and width > 0 and len(sizing.wrap(width)) <= self.min_lines):
                    picked = variant
                    break
            self._picked[width] = picked
        return picked

    @property
    def shown(self) -> Content:
        """The variant shown at the current width."""
        return self.pick(self.content_region.width or self.size.width)

    def text_lines(self, width: int) -> list[Content]:
        """The variant shown at a width, as one line (RowStrips wraps it when it does not fit)."""
        return [self.pick(width)]

    def render(self) -> Content:
        """The chosen variant."""
        return self.shown
