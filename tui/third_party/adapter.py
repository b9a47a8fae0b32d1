"""The one place that adapts plotext, textual-plotext and Textual internals.

The explorer reaches into private code of three packages for speed; all of
that lives here, written against the releases in `PINNED`. `activate()`, called
when the app starts, reads the installed versions once and turns on only the
adapters whose packages match; the others leave the stock path in place, and
`status()` says which is which (the app logs it, `jointid --version` prints it).

Importing this module changes nothing and loads none of the three packages
(each is imported where it is first needed), so `jointid --version` stays cheap.
"""

from __future__ import annotations

import importlib.util
import os
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Callable, ClassVar

if TYPE_CHECKING:
    from rich.style import Style
    from textual.screen import Screen
    from textual.strip import Strip
    from textual_plotext import PlotextPlot

PINNED = {"textual": "8.2.8", "textual-plotext": "1.0.1", "plotext": "5.3.2"}
"""The releases whose internals this module was written against (pyproject.toml pins the same)."""

PLOTEXT_HELPERS = "plotext-helpers"
"""Adapter: tui/plotext_speedups.py's drop-ins for five plotext internals (bench_tui_keys --adapter has the figure)."""
CHART_MATRIX = "chart-matrix"
"""Adapter: torque charts become strips straight from plotext's cell matrix, not via ANSI text."""
NUMBER_FIELDS = "number-fields"
"""Adapter: a number field's new value repaints the field instead of relayouting the screen."""
MODAL_BURSTS = "modal-bursts"
"""Adapter: a modal screen ignores what its widgets report after it closed or was covered (see `BurstGuard`)."""
NOTICE_KINDS = "notice-kinds"
"""Adapter: a new notification takes down the shown ones of its title (`forget_notifications`)."""
NOTICE_PATHS = "notice-paths"
"""Adapter: a notification draws a long path wrapped between its folders, its text unchanged (`ToastPaths`)."""


@dataclass(frozen=True)
class Adapter:
    """One use of third-party internals, the packages it depends on, and how its status reads.

    Attributes:
        key: The name `active()` is asked with.
        packages: Distributions whose pinned versions it needs.
        active_text: Status when in use.
        stock_text: Status when a package differs and the stock path is used instead.
    """

    key: str
    packages: tuple[str, ...]
    active_text: str
    stock_text: str


ADAPTERS = (
    Adapter(PLOTEXT_HELPERS, ("plotext",), "fast chart helpers active", "stock chart helpers"),
    Adapter(CHART_MATRIX, ("plotext", "textual-plotext"), "direct chart strips active",
            "stock chart rendering (PlotextPlot.render, slower)"),
    Adapter(NUMBER_FIELDS, ("textual",), "repaint-only number fields active",
            "stock number fields (a new value relayouts the screen)"),
    Adapter(MODAL_BURSTS, ("textual",), "modal screens safe from key bursts",
            "stock modal screens (Enter Enter can close one twice and end the app)"),
    Adapter(NOTICE_KINDS, ("textual",), "one notification per title",
            "stock notifications (those of one title stack)"),
    Adapter(NOTICE_PATHS, ("textual",), "paths in notifications wrap between folders",
            "stock notifications (a long path wraps mid-name)"),
)
"""Every adapter, in status order."""

_in_use: dict[str, bool] | None = None
"""Adapter key -> in use, set once by `activate()`; None before (every adapter is off then)."""
_status: list[str] = []
"""The status lines of that activation."""


def installed_version(distribution: str) -> str | None:
    """The installed version of a distribution, or None when it is not installed.

    Read from the name of the `<name>-<version>.dist-info` folder beside the package
    when there is one, which keeps importlib.metadata out of the explorer's start
    (tui/command.py has the figure).
    """
    version = _version_beside_package(distribution)
    if version is not None:
        return version
    from importlib import metadata  # an unusual installation: ask the standard way

    try:
        return metadata.version(distribution)
    except metadata.PackageNotFoundError:
        return None


def _version_beside_package(distribution: str) -> str | None:
    """The version in the name of the distribution's dist-info folder next to its package, or None."""
    module = distribution.replace("-", "_")
    spec = importlib.util.find_spec(module)
    if spec is None or not spec.submodule_search_locations:
        return None
    folder = Path(next(iter(spec.submodule_search_locations))).parent
    prefix = f"{module}-"
    for entry in os.listdir(folder):
        if entry.lower().startswith(prefix) and entry.endswith(".dist-info"):
            return entry[len(prefix):-len(".dist-info")]
    return None


def check() -> tuple[dict[str, bool], list[str]]:
    """Compare the installed versions with `PINNED`: which adapters may be used, and one status line each."""
    versions = {name: installed_version(name) for name in PINNED}  # each read once
    usable, lines = {}, []
    for adapter in ADAPTERS:
        usable[adapter.key] = all(versions[name] == PINNED[name] for name in adapter.packages)
        text = adapter.active_text if usable[adapter.key] else adapter.stock_text
        lines.append(f"{_describe_versions(adapter.packages, versions)}: {text}")
    return usable, lines


def _describe_versions(packages: tuple[str, ...], versions: dict[str, str | None]) -> str:
    described = []
    for name in packages:
        version, pinned = versions[name], PINNED[name]
        if version == pinned:
            described.append(f"{name} {version}")
        elif version is None:
            described.append(f"{name} not installed (expected {pinned})")
        else:
            described.append(f"{name} {version} (expected {pinned})")
    return ", ".join(described)


def activate() -> list[str]:
    """Check the versions and turn on the adapters that match, once; returns the status lines.

    Later calls change nothing and return the same lines, so every app start
    (and every test that builds charts outside the app) may call it.
    """
    global _in_use, _status
    if _in_use is None:
        usable, lines = check()
        if usable[PLOTEXT_HELPERS]:
            _put_plotext_helpers(fast=True)
        if usable[MODAL_BURSTS]:
            BurstGuard.install()
        if usable[NOTICE_PATHS]:
            ToastPaths.install()
        _in_use, _status = usable, lines
    return list(_status)


def uninstall() -> None:
    """Put plotext's own functions back and turn every adapter off; the next `activate()` checks again."""
    global _in_use, _status
    if _in_use is not None and _in_use[PLOTEXT_HELPERS]:
        _put_plotext_helpers(fast=False)
    if _in_use is not None and _in_use[MODAL_BURSTS]:
        BurstGuard.uninstall()
    if _in_use is not None and _in_use[NOTICE_PATHS]:
        ToastPaths.uninstall()
    _in_use, _status = None, []


def active(key: str) -> bool:
    """Whether an adapter (`PLOTEXT_HELPERS`, `CHART_MATRIX`, `NUMBER_FIELDS`, `MODAL_BURSTS`, `NOTICE_KINDS`) is
    in use."""
    return _in_use is not None and _in_use[key]


def status() -> list[str]:
    """One line per adapter: the versions and whether it is in use; without an activation, what one would do."""
    return list(_status) if _in_use is not None else check()[1]


# plotext ----------------------------------------------------------------------------------------


def _put_plotext_helpers(fast: bool) -> None:
    from . import plotext_speedups as speedups

    functions = speedups.FAST if fast else speedups.ORIGINALS
    for name, owner in speedups.OWNERS.items():
        setattr(owner, name, functions[name])


def new_figure():
    """A bare plotext figure, as PlotextPlot holds one (for tests and benchmarks outside the app)."""
    from plotext._figure import _figure_class

    return _figure_class()


def build_matrix(plot, width: int, height: int, theme: str | None = None):
    """Lay out a set-up plotext figure at a size (and theme) and return its matrix of cells.

    These are the steps of plotext's `build()` before it prints the matrix as
    ANSI text, which the direct renderer skips.
    """
    plot.plotsize(width, height)
    plot._set_size(width, height)  # as PlotextPlot.render does; see its comment
    if theme is not None:
        plot.theme(theme)
    plot._set_sizes()
    plot._build_matrix()
    return plot.monitor.matrix


@lru_cache(maxsize=512)
def cell_style(foreground, style, background) -> Style:
    """The Rich style of one plotext cell, decoded from exactly the ANSI code plotext would print."""
    from plotext import _utility as plotext_utility
    from rich.style import Style
    from rich.text import Text

    ansi = plotext_utility.colors_to_ansi(foreground, style, background)
    text = Text.from_ansi(f"{ansi}x{plotext_utility.ansi_end}")
    return Style.combine(span.style for span in text.spans) if text.spans else Style()


def plotext_theme_name(widget: PlotextPlot) -> str:
    """The plotext theme a PlotextPlot registered for the app's current theme."""
    return widget._get_plotext_theme_name(widget.app.theme)


def figure_strips(widget: PlotextPlot, width: int, height: int) -> list[Strip]:
    """A PlotextPlot's set-up figure as one strip per line, read from plotext's cell matrix.

    The stock widget prints the figure to an ANSI string and parses it back; this
    gives the same cells without the text, which buys 0.52 of a key press's latency
    (median; bench_tui_keys --adapter chart-matrix).
    """
    from rich.segment import Segment
    from textual.strip import Strip

    matrix = build_matrix(widget.plt, width, height, plotext_theme_name(widget))
    strips = []
    for row in reversed(matrix.Rows):  # plotext's row 0 is the bottom line
        markers = matrix.marker[row]
        key = (width, tuple(markers), tuple(matrix.fullground[row]), tuple(matrix.style[row]),
               tuple(matrix.background[row]))
        strip = _row_strips.get(key)
        if strip is None:  # a row no recent figure had (the axes, ticks and labels' rows mostly repeat)
            colours = list(zip(*key[2:]))
            segments, start = [], 0
            for col in range(1, len(markers) + 1):
                if col == len(markers) or colours[col] != colours[start]:
                    segments.append(Segment("".join(markers[start:col]), cell_style(*colours[start])))
                    start = col
            strip = _row_strips[key] = Strip(segments, width)
            if len(_row_strips) > ROW_CACHE_SIZE:
                del _row_strips[next(iter(_row_strips))]  # the oldest
        strips.append(strip)
    return strips


ROW_CACHE_SIZE = 2048
"""Chart rows kept as strips (about 70 figures of 28 rows: stepping back and forth repeats recent ones)."""
_row_strips: dict[tuple, Strip] = {}


# Textual --------------------------------------------------------------------------------------


class RepaintOnValue:
    """Mixin for a fixed-width Input: a new value repaints the field instead of relayouting the screen.

    Input's value watcher sets its virtual size through the reactive, whose
    layout flag relayouts the whole screen whenever the text's width changes
    (Reset from seed 107 to 7); the field's own width is fixed, so a repaint is
    enough. The replacement also posts no `Input.Changed` and leaves the cursor
    alone: the stepper commits on Enter, blur and steps, not on each change.
    It buys 0.98 of a key press's p95 latency (0.035 of the median; bench_tui_keys --adapter number-fields).
    """

    def _watch_value(self, value: str) -> None:
        if not active(NUMBER_FIELDS):
            super()._watch_value(value)
            return
        from textual.geometry import Size
        from textual.widgets import Input

        self.set_reactive(Input.virtual_size, Size(self.content_width, 1))
        self._suggestion = ""
        self.refresh()


class BurstGuard:
    """The one guard for key bursts on modal screens (every dialog, the joint picker, Textual's command palette).

    Key repeat and SSH batching deliver Enter Enter as one batch. Both presses reach the dialog's field or list
    before the first one's result closes it, so the field reports two submissions (the list two selections)
    and Textual's stock dialogs close twice: the second `dismiss` pops the screen beneath, and then the last
    screen (ScreenStackError, the app ends). Two rules, installed on `ModalScreen` once at start-up, stop that:

    - A message from one of a modal screen's widgets (one with a `control`: Input.Submitted,
      OptionList.OptionSelected, Button.Pressed...) that reaches the screen after it stopped being the active
      screen is dropped: it was meant for a dialog that has closed, or that another dialog now covers.
    - `dismiss` on a screen that has already left the screen stack does nothing (a worker's result arriving
      after Escape closed its dialog, say), instead of closing whichever screen is on top; on a screen that
      another covers (the command palette opened over a dialog whose worker then finishes) it first closes
      the screens above. Stock Textual closed the top screen and called the covered one's result callback
      then, and again when it was closed later (InvalidStateError, the app ends).

    The rules wrap `MessagePump._on_message`, which dispatches a message to its handlers, and `Screen.dismiss`
    of the pinned Textual; with another release they are not installed.

    The guard never reorders keys: that a burst's Enter or Backspace runs after the characters typed after it is
    Textual's own order (an Input types characters as they arrive but runs its bound keys once they have bubbled
    up to the app; Textualize/textual#6605), which tests/tui/test_key_bursts.py pins with the guard and without.
    """

    _stock: ClassVar[dict[str, Callable]] = {}
    """The methods replaced, by name, while installed."""

    @classmethod
    def install(cls) -> None:
        """Put the two rules on ModalScreen (and so on every dialog, Textual's own included)."""
        from textual.screen import ModalScreen

        if cls._stock:
            return
        cls._stock = {"_on_message": ModalScreen._on_message, "dismiss": ModalScreen.dismiss}
        ModalScreen._on_message = cls._on_message
        ModalScreen.dismiss = cls._dismiss

    @classmethod
    def uninstall(cls) -> None:
        """Give ModalScreen its inherited methods back."""
        from textual.screen import ModalScreen

        for name in cls._stock:
            delattr(ModalScreen, name)  # the stock methods are inherited: removing the rule uncovers them
        cls._stock = {}

    @staticmethod
    def stale(screen: Screen, message) -> bool:
        """Whether `message` is a widget's report that arrived after `screen` stopped being the active screen."""
        from textual.events import Event

        return message.control is not None and not isinstance(message, Event) and not screen.is_active

    @staticmethod
    async def _on_message(screen: Screen, message) -> None:
        if BurstGuard.stale(screen, message):
            return
        await BurstGuard._stock["_on_message"](screen, message)

    @staticmethod
    def _dismiss(screen: Screen, result=None):
        from textual.await_complete import AwaitComplete

        stack = screen.app.screen_stack
        if screen not in stack:  # dismissed already: closing again would close another screen
            return AwaitComplete.nothing()
        if stack[-1] is not screen:  # covered: close what is above it, then dismiss it as the top screen
            screen.pop_until_active()
            screen.app.call_later(BurstGuard._dismiss, screen, result)
            return AwaitComplete.nothing()
        return BurstGuard._stock["dismiss"](screen, result)


class ToastPaths:
    """Textual's notification box, drawing a path too long for its line broken after the path's separators
    (tui/notices.py's fold_paths) rather than folded mid-name; the notification's text stays one line.

    Replaces `Toast.render` of the pinned Textual with the same assembly of title and message, the message's
    long paths folded for the box's width; with another release the stock render stays.
    """

    _stock: ClassVar[Callable | None] = None
    """Toast.render while replaced."""

    @classmethod
    def install(cls) -> None:
        """Draw notifications through `_render`."""
        from textual.widgets._toast import Toast

        if cls._stock is None:
            cls._stock, Toast.render = Toast.render, cls._render

    @classmethod
    def uninstall(cls) -> None:
        """Give Toast its own render back."""
        from textual.widgets._toast import Toast

        if cls._stock is not None:
            Toast.render, cls._stock = cls._stock, None

    @staticmethod
    def _render(toast):
        from textual.content import Content

        from ..notices import fold_paths, toast_text_width

        notification = toast._notification
        message = fold_paths(notification.message, toast_text_width(toast.app.size.width))
        content = Content.from_markup(message) if notification.markup else Content(message)
        if notification.title:
            content = Content.assemble((notification.title, toast.get_visual_style("toast--title")), "\n", content)
        return content


def forget_notifications(app, title: str) -> None:
    """Remove the app's notifications with this title without redrawing them (the new one's arrival redraws).

    Textual keeps notifications in a private collection and removes one by a private method; with another
    release nothing is removed and notifications stack as stock Textual's do.
    """
    if not active(NOTICE_KINDS):
        return
    for notification in [n for n in app._notifications if n.title == title]:
        app._unnotify(notification, refresh=False)


def _require_pinned_textual(what: str) -> None:
    version = installed_version("textual")
    if version != PINNED["textual"]:
        raise RuntimeError(f"{what} reads Textual {PINNED['textual']} internals; "
                           f"textual {version} is installed: update it in tui/third_party.py")


def after_compositor_refresh(callback: Callable[[Screen], None]) -> Callable[[], None]:
    """Call `callback(screen)` after every screen refresh (benchmarks time frames with it); returns an undo.

    Raises:
        RuntimeError: The installed Textual is not the pinned one, whose refresh method this wraps.
    """
    _require_pinned_textual("after_compositor_refresh")
    return _call_after_screen_method("_compositor_refresh", callback)


def after_screen_update(callback: Callable[[Screen], None]) -> Callable[[], None]:
    """Call `callback(screen)` after every frame of a screen's update timer, layout included; returns an undo.

    A frame that lays out the screen paints (`_compositor_refresh`) before Textual clears its layout flag,
    so `screen_settled` read in an `after_compositor_refresh` callback calls such a frame unsettled; read
    here, after the whole frame, it is exact (benchmarks/bench_design.py: with a progress readout laying
    out the screen most frames, no key's frame ever looked settled there).

    Raises:
        RuntimeError: The installed Textual is not the pinned one, whose update method this wraps.
    """
    _require_pinned_textual("after_screen_update")
    return _call_after_screen_method("_on_timer_update", callback)


def _call_after_screen_method(name: str, callback: Callable[[Screen], None]) -> Callable[[], None]:
    # Wraps Screen.<name> so that callback(screen) runs after it; the undo puts the original back.
    from textual.screen import Screen

    original = getattr(Screen, name)

    def call_then_callback(screen: Screen) -> None:
        original(screen)
        callback(screen)

    setattr(Screen, name, call_then_callback)

    def undo() -> None:
        setattr(Screen, name, original)

    return undo


def app_exception(app) -> BaseException | None:
    """The exception an app ended by, or None (Textual keeps the first one in a private attribute)."""
    return getattr(app, "_exception", None)  # absent in another release: fall back to the return code


def screen_settled(screen: Screen) -> bool:
    """True when a screen has nothing left to lay out or paint (read in an `after_compositor_refresh` callback)."""
    return not (screen._layout_required or screen._dirty_widgets or screen._repaint_required)
