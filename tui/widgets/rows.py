"""Text widgets that build each row's strip once per distinct text and repaint only the rows that changed.

A key press changes some of the readouts' rows and the status sentence, not all
of them (the rank, the motion's RMS rows, the closing notes, the blank reserved
rows stay). Textual re-renders a refreshed widget whole: every row's content,
then every row's styling and compositing, about 50 to 100 µs a row. Here a row
whose text did not change keeps its strip and is not repainted at all; a row
whose text did is rendered once (and kept, so stepping back costs nothing).
"""

from __future__ import annotations

from collections import OrderedDict

from textual.content import Content
from textual.geometry import Region
from textual.strip import Strip
from textual.visual import Visual
from textual.widget import Widget

LINE_CACHE_SIZE = 1024
"""Rendered rows kept (a screen shows about 30 text rows; stepping back and forth revisits recent ones)."""

_line_strips: OrderedDict[tuple, Strip] = OrderedDict()


def content_key(content: Content) -> tuple:
    """What a Content renders from: its text and its spans (Content's own equality compares the text only)."""
    return content.plain, tuple(content.spans)


def line_strip(widget: Widget, line: Content, y: int, width: int) -> Strip:
    """Row `y` of a text whose line there fits `width`, as Textual renders it in `widget`; built once per text,
    row, width and style.

    The row matters: Textual's strips carry each cell's (column, row) in the text, for selecting
    text with the mouse. Rendered after y empty lines, the line gets exactly the strip the whole
    text would give it (the lines of a text are formatted independently).
    """
    style = widget.visual_style
    key = (content_key(line), y, width, style, widget.styles.content_align, widget.auto_links)
    strip = _line_strips.get(key)
    if strip is None:
        strip = Visual.to_strips(widget, Content("\n" * y) + line if y else line, width, y + 1, style)[y]
        _line_strips[key] = strip
        if len(_line_strips) > LINE_CACHE_SIZE:
            _line_strips.popitem(last=False)
    else:
        _line_strips.move_to_end(key)
    return strip


def refresh_changed_rows(widget: Widget, shown: list[Strip], new: list[Strip]) -> None:
    """Repaint the rows of `widget` whose strips differ between `shown` (on screen) and `new`; all of them when
    the row count changed."""
    if len(shown) != len(new):
        widget.refresh()
        return
    width = widget.size.width
    changed = [Region(0, y, width, 1) for y, (before, after) in enumerate(zip(shown, new)) if before != after]
    if changed:
        widget.refresh(*changed)


class RowStrips(Widget):
    """A widget whose `render()` is Content, painted row by row from `row_strips()`.

    Subclasses give their text as lines (`text_lines`); when every line fits the
    width each row is one cached `line_strip`, otherwise the whole text is
    rendered as Textual would (wrapped). `refresh_rows()` repaints only the rows
    whose strips differ from the ones on screen.
    """

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self._rows: list[Strip] = []
        self._rows_key: tuple | None = None

    def text_lines(self, width: int) -> list[Content]:
        """The text's lines at a width, before any wrapping."""
        raise NotImplementedError

    def row_strips(self) -> list[Strip]:
        """The strips of the rows at the current size and style (rebuilt only when those or the text changed)."""
        width, height = self.size
        lines = self.text_lines(width)
        key = (tuple(map(content_key, lines)), width, height, self.visual_style, self.styles.content_align,
               self.auto_links, self.text_selection)
        if key == self._rows_key:
            return self._rows
        if self.text_selection is None and all(
                line.cell_length <= width and "\n" not in line.plain for line in lines):
            strips = [line_strip(self, line, y, width) for y, line in enumerate(lines[:height])]
        else:  # wrapped text or a selection: Textual's own rendering of the whole text
            strips = Visual.to_strips(self, Content("\n").join(lines), width, height, self.visual_style)
        self._rows, self._rows_key = strips, key
        return strips

    def render_line(self, y: int) -> Strip:
        """One row (Textual's line API): its cached strip, blank below the text."""
        width = self.size.width
        strips = self.row_strips() if width > 0 else []
        if 0 <= y < len(strips):
            return strips[y]
        return Strip.blank(width, self.visual_style.rich_style)

    def refresh_rows(self) -> None:
        """Repaint the rows whose strips changed since the last paint (all of them when the row count changed)."""
        width = self.size.width
        if not width or self._rows_key is None:
            self.refresh()
            return
        old = self._rows
        refresh_changed_rows(self, old, self.row_strips())
