"""The key footer: the keys that work now, on one line drawn by one widget."""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from itertools import groupby

from textual.actions import parse
from textual.app import App
from textual.binding import Binding
from textual.content import Content
from textual.screen import Screen
from textual.widget import Widget


@dataclass(frozen=True)
class KeyEntry:
    """One footer item: its key or keys as displayed, what they do, and whether they work now."""

    keys: str
    description: str
    enabled: bool = True
    parts: tuple[KeyEntry, ...] = ()
    """A group's own entries, shown one by one when the width has room (see EXPANDED_WHEN_ROOM)."""
    action: str = ""
    """The binding's action ("" for a group's shared entry), for DROPPED_WHEN_TIGHT."""


EXPANDED_WHEN_ROOM = {"Views"}
"""Groups whose keys get an entry each when they fit ("s Sweep  m Matrix ..."), and one shared
entry ("s m e l Views") only when the footer is tight; other groups always share one."""


def key_entries(screen: Screen, app: App) -> tuple[tuple[KeyEntry, ...], KeyEntry | None]:
    """The shown bindings of the focused widget and its screen, and the command palette's key.

    As in Textual's footer: one entry per action (its first key), and bindings of
    one group with more than one action share an entry, "1 2 3 Motion".
    """
    active = screen.active_bindings
    entries = grouped_entries([(binding, enabled) for _, binding, enabled, _ in active.values()], app)
    palette = None
    if app.ENABLE_COMMAND_PALETTE and app.COMMAND_PALETTE_BINDING in active:
        _, binding, enabled, _ = active[app.COMMAND_PALETTE_BINDING]
        palette = KeyEntry(app.get_key_display(binding), binding.description, enabled)
    return entries, palette


def focus_free_entries(screen: Screen, app: App) -> tuple[KeyEntry, ...]:
    """The entries shown now, plus the screen's keys a focused field takes as typing (1 2 3 in a number field).

    The footer picks its spacing for these, so that focus changes which keys show but never
    the spacing or whether the palette's key fits (docs/explorer.md, "Keys").
    """
    active = screen.active_bindings
    members = [(binding, enabled) for _, binding, enabled, _ in active.values()]
    shown_actions = {binding.action for binding, _ in members}
    for binding in screen.BINDINGS:
        if not isinstance(binding, Binding) or not binding.show or binding.action in shown_actions:
            continue
        _, name, parameters = parse(binding.action)
        state = screen.check_action(name, parameters)
        if state is not False:  # False: hidden for now whatever is focused
            members.append((binding, bool(state)))
            shown_actions.add(binding.action)
    order = {binding.action: index for index, binding in enumerate(screen.BINDINGS) if isinstance(binding, Binding)}
    members.sort(key=lambda member: order.get(member[0].action, len(order)))  # stable: others keep their order
    return grouped_entries(members, app)


def grouped_entries(members: list[tuple[Binding, bool]], app: App) -> tuple[KeyEntry, ...]:
    """One entry per shown action, the members of a group sharing one ("1 2 3 Motion")."""
    by_action: dict[str, tuple] = {}
    for binding, enabled in members:
        if binding.show:
            by_action.setdefault(binding.action, (binding, enabled))
    entries = []
    for group, grouped in groupby(by_action.values(), lambda member: member[0].group):
        grouped = list(grouped)
        if group is not None and len(grouped) > 1:
            keys = " ".join(app.get_key_display(binding) for binding, _ in grouped)
            parts = tuple(KeyEntry(app.get_key_display(binding), binding.description, enabled)
                          for binding, enabled in grouped) if group.description in EXPANDED_WHEN_ROOM else ()
            entries.append(KeyEntry(keys, group.description, any(enabled for _, enabled in grouped), parts))
        else:
            entries.extend(KeyEntry(app.get_key_display(binding), binding.description, enabled, action=binding.action)
                           for binding, enabled in grouped)
    return tuple(entries)


@lru_cache(maxsize=256)
def entry_content(entry: KeyEntry) -> Content:
    """A key in the footer's key colour, a space, then its description ("r Reset": one form at every width).

    Remembered: parsing the markup took about 80 µs an entry, and the footer is drawn several
    times before the first frame is up with the same entries (Content is immutable).
    """
    content = Content.from_markup("[b $footer-key-foreground]$keys[/]", keys=entry.keys)
    if entry.description:
        content += Content(" " + entry.description)
    return content if entry.enabled else content.stylize("dim")


ARRANGEMENTS = (("  ", "full"), ("  ", "key"), (" ", "full"), (" ", "key"), (" ", None))
"""(between entries, the palette shown in full, as its key or not at all), roomiest first. A key and
its description are always one space apart; the palette's key gives way before any key's name."""

DROPPED_WHEN_TIGHT = ("quit",)
"""Actions whose entry leaves the footer when the keys do not fit otherwise (80 columns): q is the
convention for leaving, and help and the palette list it. Every other main-screen key stays."""


def footer_line(entries: tuple[KeyEntry, ...], palette: KeyEntry | None, width: int,
                spacing_for: tuple[KeyEntry, ...] | None = None) -> Content:
    """The roomiest arrangement that fits the width, the palette's key at the right end.

    Groups in EXPANDED_WHEN_ROOM show their keys one by one while any arrangement
    fits that way; then they share one entry; then the entries of DROPPED_WHEN_TIGHT
    leave. The arrangement is the roomiest in which `spacing_for` fits (the entries
    themselves by default), or a tighter one the entries need. When even the tightest
    is too wide, the keys that are off for now (dimmed) are left out, groups' too;
    then the keys that fit are shown and "…". Help and the palette list every key.
    """
    first = _first_fitting(spacing_for, palette, width) if spacing_for is not None else 0
    tries = _tries(entries)
    for shown, (separator, palette_shown) in tries[first:]:
        right, line = _arranged(shown, palette, separator, palette_shown)
        if line.cell_length <= _room(width, right):
            break
    else:
        room = _room(width, right)
        kept = []
        for entry in shown:
            if Content(separator).join([*kept, entry_content(entry), Content("…")]).cell_length > room:
                break
            kept.append(entry_content(entry))
        line = Content(separator).join([*kept, Content("…")])
    return line + Content(" " * max(0, width - line.cell_length - right.cell_length)) + right


def _tries(entries: tuple[KeyEntry, ...]) -> list[tuple[tuple[KeyEntry, ...], tuple]]:
    """(entries, arrangement) roomiest first: groups expanded, then shared, then without the droppable
    entries, then only the working keys."""
    expanded = tuple(part for entry in entries for part in (entry.parts or (entry,)))
    kept = tuple(entry for entry in entries if entry.action not in DROPPED_WHEN_TIGHT)
    working = tuple(_working(entry) for entry in kept if entry.enabled)
    return [*((expanded, a) for a in ARRANGEMENTS), *((entries, a) for a in ARRANGEMENTS),
            (kept, ARRANGEMENTS[-1]), (working, ARRANGEMENTS[-1])]


def _first_fitting(entries: tuple[KeyEntry, ...], palette: KeyEntry | None, width: int) -> int:
    """The index in `_tries` of the roomiest arrangement in which these entries fit (the last if none)."""
    tries = _tries(entries)
    for index, (shown, (separator, palette_shown)) in enumerate(tries):
        right, line = _arranged(shown, palette, separator, palette_shown)
        if line.cell_length <= _room(width, right):
            return index
    return len(tries) - 1


def _arranged(shown, palette, separator, palette_shown) -> tuple[Content, Content]:
    """The palette's part and the keys' line of one arrangement."""
    right = palette_content(palette, palette_shown)
    return right, Content(separator).join(entry_content(entry) for entry in shown)


def _room(width: int, right: Content) -> int:
    """Columns left for the keys: a space separates them from the palette's part, when there is one."""
    return width - right.cell_length - (1 if right.cell_length else 0)


def _working(entry: KeyEntry) -> KeyEntry:
    """A group's entry with only its keys that work now (any other entry as it is)."""
    if not entry.parts:
        return entry
    keys = " ".join(part.keys for part in entry.parts if part.enabled)
    return KeyEntry(keys, entry.description, entry.enabled)


def palette_content(palette: KeyEntry | None, shown: str | None) -> Content:
    """The palette's entry at the right end: in full, as its key, or nothing."""
    if palette is None or shown is None:
        return Content("")
    entry = palette if shown == "full" else KeyEntry(palette.keys, "", palette.enabled)
    return Content.from_markup("[dim]│[/] ") + entry_content(entry)


class KeyFooter(Widget):
    """The keys that work now, in one widget: Textual's footer mounts one widget per key.

    Textual's footer rebuilt its dozen key widgets on every focus change that
    changed the keys (a number field hides 1 2 3 and e, which it takes as
    typing); that relayout landed on the next key press, and the widgets
    cost start-up time. This one re-renders a line of text. Below the width
    of every key, it tightens the spacing between entries, then drops Quit, then
    shows the keys that fit and "…".

    Why not the stock Footer: at 80 columns it cut Ctrl+O to "^oO" and dropped
    Export, where this one shows every key of the main screen but Quit (tests/tui/test_footer.py);
    and it is one widget instead of one per key (with the other start-up changes
    made with it, the main screen went from about 55 widgets and 183 style rules
    to 32 and 85; benchmarks/bench_tui_startup.py measures start-up).
    """

    DEFAULT_CSS = """
    KeyFooter {
        dock: bottom;
        height: 1;
        padding: 0 1;
        background: $footer-background;
        color: $footer-description-foreground;
    }
    """

    ALLOW_SELECT = False

    def __init__(self) -> None:
        """Create an empty footer; it fills when the screen reports its bindings."""
        super().__init__()
        self.entries: tuple[KeyEntry, ...] = ()
        self.palette: KeyEntry | None = None
        self.spacing_for: tuple[KeyEntry, ...] = ()
        """The entries the spacing is chosen for: those shown with the keys a focused field types added back."""
        self._line: tuple[int, Content] | None = None
        """(width, line) last rendered; the footer repaints with every frame that reaches it."""

    def on_mount(self) -> None:
        """Follow the screen's bindings (they change with focus and with check_action)."""
        self.screen.bindings_updated_signal.subscribe(self, self.bindings_changed)
        self.bindings_changed(self.screen)

    def on_unmount(self) -> None:
        """Stop following the screen's bindings."""
        self.screen.bindings_updated_signal.unsubscribe(self)

    def bindings_changed(self, screen: Screen) -> None:
        """Redraw only if the keys, their descriptions or their enabled state changed."""
        if screen is not self.screen or not self.app.app_focus:
            return
        entries, palette = key_entries(screen, self.app)
        spacing_for = focus_free_entries(screen, self.app)
        if (entries, palette, spacing_for) != (self.entries, self.palette, self.spacing_for):
            self.entries, self.palette, self.spacing_for = entries, palette, spacing_for
            self._line = None
            self.refresh()

    @property
    def text(self) -> str:
        """The footer as shown at its current width, without styles (for tests)."""
        return self.render().plain

    def render(self) -> Content:
        """The keys arranged for the current width."""
        width = self.content_size.width
        if self._line is None or self._line[0] != width:
            self._line = (width, footer_line(self.entries, self.palette, width, self.spacing_for))
        return self._line[1]
