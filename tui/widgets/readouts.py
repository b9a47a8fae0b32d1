"""The lab's readouts and the status sentence, rendered from the core's own readout text."""

from __future__ import annotations

from functools import lru_cache

from textual.content import Content

from jointid.estimation.uncertainty import NOT_DETERMINED, WEAK, WELL_DETERMINED
from jointid.present.readouts import Precision, PrecisionNote, Readout

from .rows import RowStrips

LABEL_WIDTH = 27
"""Columns reserved for a readout label ("Fitted damping (N m s/rad)" and a space); longer
labels of other models' terms widen the column."""
COMPACT_LABEL_WIDTH = 26
"""Columns for a label in compact rows ("Acceleration RMS (rad/s²)" and a space)."""
COMPACT_VALUE_WIDTH = 9
"""Columns a compact parameter value is right-aligned in ("-1.607788"), so the ± line up."""
RESERVED_FAILURE_LINES = 2
"""Rows kept for sign-failure notes on lines of their own, blank while no sign fails (slow
motion with much noise breaks two requirements, I > 0 and B ≥ 0)."""
COMPACT_RESERVED_FAILURE_LINES = 1
"""Compact rows kept for sign-failure notes: 80x24 has room for one."""
COMPACT_PARAMETER_ROWS = 3
"""Parameters compact rows show beside every other readout; a model with more drops MOTION_RMS_KEYS."""
MOTION_RMS_KEYS = ("accel_rms", "speed_rms")
"""Readouts of the motion rather than the fit, the first to give way on a small terminal."""

INDENT = "  "
"""Precision lines sit under their readout, indented."""

VERDICT_STYLES = {WELL_DETERMINED: "$text-success", WEAK: "$text-warning", NOT_DETERMINED: "$text-error"}
"""Theme colour of each verdict (the words carry the meaning; colour only repeats it)."""


def failure_note(readout: Readout) -> str:
    """The label that names the requirement a fitted value breaks, e.g. 'I > 0 fails'."""
    return f"{readout.failed_requirement} fails"


def note_lines(precision: Precision | None, key: str, width: int) -> list[Content]:
    """The note under readout `key` (none for readouts that are not parameters)."""
    if precision is None:
        return []
    lines = []
    for note in precision.notes:
        if note.key != key:
            continue
        line = Content(INDENT + note.text)
        if note.verdict:
            line += Content("  ") + verdict_content(note.verdict)
        lines.append(line)
    return lines


@lru_cache(maxsize=None)
def verdict_content(verdict: str) -> Content:
    """A verdict in its theme colour (the words alone carry the meaning, for NO_COLOR); parsed once per verdict."""
    return Content.from_markup(f"[{VERDICT_STYLES[verdict]}]$v[/]", v=verdict)


@lru_cache(maxsize=64)
def dim_content(text: str) -> Content:
    """Text in the dim style (markup parsing costs more than the rest of a readout line: done once a text)."""
    # dim, not $text-muted: that variable has alpha, which showed as plain text here.
    return Content.from_markup("[dim]$t[/]", t=text)


def closing_content(precision: Precision | None, label_width: int) -> list[Content]:
    """The closing lines: labelled values as the readouts have them, notes indented and dim."""
    if precision is None:
        return []
    return [
        Content(label.ljust(label_width) + text) if label else dim_content(INDENT + text)
        for label, text in precision.closing
    ]


def compact_parameter_lines(item: Readout, note: PrecisionNote, width: int,
                            failure_row: bool = True) -> list[Content]:
    """A parameter's compact row: symbol, value ± standard error and verdict, wrapped only if too wide (the
    verdict under the value and its error, or if even they do not fit, everything after the value).

    One-letter symbols keep their values right-aligned in COMPACT_VALUE_WIDTH so the ± line up;
    a longer symbol (another model's term) takes its extra columns from that padding.
    """
    if note.short and not item.sign_failure:  # no value: what the data still say about it
        return [Content(note.short)]
    value = item.text.rjust(COMPACT_VALUE_WIDTH + 1 - len(item.key))
    head = Content(f"{item.key} ") + (
        Content.from_markup("[bold $text-error]$v[/]", v=value) if item.sign_failure else Content(value)
    )
    tail = Content(note.text)
    if note.verdict:
        tail += Content(" ") + verdict_content(note.verdict)
    row = head + Content(" ") + tail
    with_error = head + Content(" ") + Content(note.text)
    if row.cell_length <= width:
        lines = [row]
    elif note.verdict and with_error.cell_length <= width:  # the value keeps its error; the verdict goes under
        lines = [with_error, Content("  ") + verdict_content(note.verdict)]
    else:
        lines = [head, Content("  ") + tail]
    if item.sign_failure and failure_row:
        failed = Content.from_markup("[bold $text-error]✗ $note[/]", note=failure_note(item))
        if lines[0].cell_length + 2 + failed.cell_length <= width:
            lines[0] += Content("  ") + failed
        else:
            lines.insert(1, Content("  ") + failed)
    return lines


class ReadoutPanel(RowStrips):
    """Eight labelled readouts; a sign failure is shown unclipped in the error colour.

    When the panel is too narrow to name the failed requirement on the value's
    line, the note goes on a line of its own under the value. Compact (small
    terminals): one row per parameter, `I  -1.607788 ± 5.425077 not determined`,
    and the condition number on one line; the known-parameters line gives the units.
    """

    DEFAULT_CSS = """
    ReadoutPanel {
        height: auto;
    }
    ReadoutPanel:focus {
        background: $primary 20%;
    }
    """

    can_focus = True

    def __init__(self, *, id: str | None = None, compact: bool = False) -> None:
        """Create an empty panel.

        Args:
            id: Widget id.
            compact: Start with one row per parameter (small terminals).
        """
        super().__init__(id=id)
        self.items: tuple[Readout, ...] = ()
        self._lines: list[Content] = []
        self._lines_key: tuple | None = None
        self.precision: Precision | None = None
        self.compact = compact

    def allow_focus(self) -> bool:
        """A Tab stop only while the panel's container scrolls: focus then scrolls the readouts into view.

        Everywhere else (80x24 and larger) every readout is on screen, and Tab
        stopping here showed nothing but a faint tint.
        """
        container = self.parent
        return self.can_focus and container is not None and getattr(container, "max_scroll_y", 0) > 0

    def set_compact(self, compact: bool) -> None:
        """Switch between the lab's labelled lines and one row per parameter (the screen decides by size)."""
        if compact != self.compact:
            self.compact = compact
            self.refresh(layout=True)

    def show(self, items: tuple[Readout, ...], precision: Precision | None = None) -> None:
        """Display new readouts and precision notes (value objects, so equal ones skip the refresh)."""
        if (items, precision) == (self.items, self.precision):
            return
        width = self.content_region.width
        old_height = self.rows(width)
        self.items, self.precision = items, precision
        # A relayout of the whole screen costs more than the rest of a key press; the rows
        # are reserved so that one is needed only when the panel really grows or shrinks.
        if not width or self.rows(width) != old_height:
            self.refresh(layout=True)
        else:
            self.refresh_rows()  # the rank, RMS and closing rows mostly stay: not repainted

    def reserved_rows(self) -> int:
        """Rows every fit fills at most in the current mode, so key presses keep the panel's height.

        Each readout's row, the precision line under each parameter (full mode),
        the sign-failure lines, and the closing lines (three in full mode, one compact).
        """
        if not self.items:
            return 0
        parameters = 0 if self.precision is None else len(self.precision.notes)
        if self.compact:
            return len(self.compact_items()) + COMPACT_RESERVED_FAILURE_LINES + 1
        return len(self.items) + parameters + RESERVED_FAILURE_LINES + 3

    def rows(self, width: int) -> int:
        """The panel's height at a width: its lines, or the reserved rows if more."""
        return max(len(self.lines(width)), self.reserved_rows())

    def lines(self, width: int) -> list[Content]:
        """The panel's lines for a given width (layout and render both ask; build once)."""
        key = (self.items, self.precision, width, self.compact)
        if self._lines_key != key:
            self._lines = self._build_compact(width) if self.compact else self._build_lines(width)
            self._lines_key = key
        return self._lines

    def compact_items(self) -> tuple[Readout, ...]:
        """The readouts compact rows show: all of them for the lesson's three parameters; with more, the motion's
        RMS rows give way (80x24 has no more rows; the full layout, the CLI and JSON keep them)."""
        parameters = 0 if self.precision is None else len(self.precision.notes)
        if parameters <= COMPACT_PARAMETER_ROWS:
            return self.items
        return tuple(item for item in self.items if item.key not in MOTION_RMS_KEYS)

    def _build_compact(self, width: int) -> list[Content]:
        items = self.compact_items()
        lines = self._compact_lines(items, width)
        if len(lines) > self.reserved_rows():  # sign failures and long values need more rows: the motion's give way
            items = tuple(item for item in items if item.key not in MOTION_RMS_KEYS)
            lines = self._compact_lines(items, width)
        if len(lines) > self.reserved_rows():  # still more: several sign failures share one row
            lines = self._compact_lines(items, width, shared_failures=True)
        return lines

    def _compact_lines(self, items: tuple[Readout, ...], width: int, shared_failures: bool = False) -> list[Content]:
        notes = {} if self.precision is None else {note.key: note for note in self.precision.notes}
        failed = [item for item in items if item.sign_failure and item.key in notes]
        shared = shared_failures and len(failed) > 1
        lines = []
        for item in items:
            note = notes.get(item.key)
            if note is None:  # rank and the RMS readouts keep their labels
                lines.append(Content(item.label.ljust(COMPACT_LABEL_WIDTH) + item.text))
                continue
            lines.extend(compact_parameter_lines(item, note, width, failure_row=not shared))
            if shared and item is failed[-1]:  # after the last failed parameter: 'x h >= 0, Fc >= 0 fail'
                names = ", ".join(failure.failed_requirement for failure in failed)
                lines.append(Content("  ") + Content.from_markup("[bold $text-error]✗ $note[/]", note=f"{names} fail"))
        if self.precision is not None and self.precision.compact_closing:
            lines.append(Content(self.precision.compact_closing))
        return lines

    def _build_lines(self, width: int) -> list[Content]:
        label_width = max([LABEL_WIDTH, *(len(item.label) + 1 for item in self.items)])
        lines = []
        for item in self.items:
            line = Content(item.label.ljust(label_width))
            if not item.sign_failure:
                lines.append(line + Content(item.text))
                lines.extend(note_lines(self.precision, item.key, width))
                continue
            note = failure_note(item)
            value = Content.from_markup("[bold $text-error]$text[/]", text=item.text)
            note_text = Content.from_markup("[bold $text-error]✗ $note[/]", note=note)
            if label_width + len(item.text) + 2 + note_text.cell_length <= width:
                lines.append(line + value + Content("  ") + note_text)
            else:
                lines.append(line + value)
                indent = max(0, min(label_width, width - note_text.cell_length))
                lines.append(Content(" " * indent) + note_text)
            lines.extend(note_lines(self.precision, item.key, width))
        return lines + closing_content(self.precision, label_width)

    def text_lines(self, width: int) -> list[Content]:
        """The readout lines at a width (RowStrips paints them row by row)."""
        return self.lines(width)

    def render(self) -> Content:
        """All readout lines for the current width."""
        return Content("\n").join(self.lines(self.size.width))

    def get_content_height(self, container, viewport, width: int) -> int:
        """The reserved rows, or more when the width pushes extra note lines down."""
        return self.rows(width)
