"""A focusable numeric stepper: Left/Right to step, Shift for big steps, or type a value."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from textual.binding import Binding
from textual.events import Blur, Key
from textual.widgets import Input

from jointid.options import SettingsError, parse_setting

from ..notices import ROUTINE_SECONDS
from ..third_party.adapter import RepaintOnValue

NUMBER_CHARACTERS = frozenset("0123456789.+-eE")
"""Characters a typed number may contain; other keys fall through to the screen's bindings."""
EXPONENT_CHARACTERS = frozenset("eE")
"""Letters a number may contain but not start with: typed only after other typing (1e-2), else the screen's keys."""


@dataclass(frozen=True)
class StepRange:
    """The explorer's range and step sizes for one numeric setting.

    Attributes:
        field: Name of the setting in `jointid.synthetic.settings` ("noise", "samples", "seed").
        low: Smallest value the control accepts.
        high: Largest value the control accepts.
        step: Change per Left/Right press.
        big_step: Change per Shift+Left/Right press.
        decimals: Decimals shown; 0 means a whole number.
        unit: Unit appended in messages ("" for none).
        label: The setting's name in messages (default: `field`, which is the core's internal name).
    """

    field: str
    low: float
    high: float
    step: float
    big_step: float
    decimals: int = 0
    unit: str = ""
    label: str = ""

    def clamp(self, value: float) -> float:
        """Value limited to [low, high], rounded to kill float drift from repeated steps."""
        value = min(max(value, self.low), self.high)
        # Stepping 0.01 a hundred times in binary floats gives 0.9999999999999999;
        # rounding well below the displayed decimals removes that drift.
        return round(value, 10) if self.decimals else int(value)

    def format(self, value: float) -> str:
        """Text for a value: fixed decimals, or more when a typed value needs them."""
        if not self.decimals:
            return str(int(value))
        text = f"{value:.{self.decimals}f}"
        return text if float(text) == value else f"{value:.10g}"

    def describe(self) -> str:
        """The range as a phrase, e.g. 'from 0.00 to 1.00 N m'."""
        unit = f" {self.unit}" if self.unit else ""
        return f"from {self.format(self.low)} to {self.format(self.high)}{unit}"

    def parse(self, text: str) -> float:
        """Typed text as a value in range, or raise SettingsError with a one-line message."""
        try:
            value = parse_setting(self.field, text)  # the core's parsing and type rules
            if self.low <= value <= self.high:
                return value
        except SettingsError:
            pass
        # One message for every refusal, naming this control's range rather than the core's
        # wider one, which the explorer cannot show.
        kind = "a number" if self.decimals else "a whole number"
        raise SettingsError(self.field, f"{self.label or self.field} must be {kind} {self.describe()}; "
                                        f"got {text.strip()!r}")


class Stepper(RepaintOnValue, Input):
    """A numeric setting that steps with Left/Right (Shift: big step) and accepts typed values.

    Typed text is committed with Enter or when focus leaves; invalid text is
    refused with a notification and the previous value is kept. Left/Right on
    typed text step from the typed value, or refuse it as Enter would. After
    Enter, a step or Escape the whole text is selected, so the next digit
    starts a new value instead of appending to the old one. With nothing typed,
    Escape is not the field's: it reaches the screen (a dialog closes), and neither is a letter that
    cannot start a number (e), so a view's key works wherever the focus was left. A new value is
    handed to the owner's `on_commit` callback (the explorer's one convention for
    widgets reporting up: see tui/widgets/direct_controls.py for the measured reason);
    the owner, holding the one copy of the state, shows it with `show_value`.
    """

    DEFAULT_CSS = """
    Stepper {
        width: 14;
    }
    """

    BINDINGS = [
        Binding("left", "step(-1)", "Step down", show=False),
        Binding("right", "step(1)", "Step up", show=False),
        Binding("shift+left", "step(-1, True)", "Big step down", show=False),
        Binding("shift+right", "step(1, True)", "Big step up", show=False),
        Binding("escape", "revert", "Discard typing", show=False),
    ]

    def __init__(self, steps: StepRange, value: float | None = None, *,
                 on_commit: Callable[[str, float], None], command_keys: str = "",
                 id: str | None = None) -> None:
        """Create a stepper.

        Args:
            steps: Range and step sizes.
            value: Value to show first (clamped into range); None shows nothing until `show_value`.
            on_commit: Called with the field and a new valid value; the owner keeps the value
                and shows it back with `show_value`.
            command_keys: Characters that are the owner's (non-priority) key bindings while
                nothing is typed here, and typed like any other while something is.
            id: Widget id.
        """
        self.steps = steps
        self.command_keys = frozenset(command_keys)
        self.number = steps.low if value is None else steps.clamp(value)
        """The value on display, as the owner last showed it: steps start from here."""
        self._on_commit = on_commit
        self._shown = "" if value is None else steps.format(self.number)
        """The text the owner last showed: anything else in the field is the user's typing."""
        self._was_editing = False
        super().__init__(value=self._shown, id=id, compact=True)

    def letter_passes(self, character: str | None) -> bool:
        """Whether a letter goes on to the screen's keys: one that cannot start a number (e) or a command key,
        while nothing is typed here (the field merely shows its value, however it got the focus)."""
        return character is not None and character in (self.command_keys | EXPONENT_CHARACTERS) and not self.editing

    def check_consume_key(self, key: str, character: str | None) -> bool:
        """Claim characters a number can contain (r, ? and q stay global); e and command keys only while typing."""
        if self.letter_passes(character):
            return False
        return character is not None and (character in NUMBER_CHARACTERS or character in self.command_keys)

    def _on_key(self, event: Key) -> None:
        # Decided here, in order with the keys typed before it: a priority binding on the
        # screen is decided when the key arrives, before this field has taken those keys.
        # Textual runs this before Input's own key handler, as a subclass's handler.
        if self.letter_passes(event.character):
            event.prevent_default()  # Input would type it; not stopped, it reaches the owner's binding

    @property
    def field(self) -> str:
        """Name of the setting this stepper controls."""
        return self.steps.field

    @property
    def editing(self) -> bool:
        """True while the field holds typing that is neither committed nor refused yet."""
        return self.value != self._shown

    def show_value(self, value: float | str) -> None:
        """Display the owner's value (or a text such as 'from log') without reporting it back."""
        if isinstance(value, str):
            text = value
        else:
            self.number = value
            text = self.steps.format(value)
        self._shown = text
        if self.value != text:
            with self.prevent(Input.Changed):
                self.value = text

    def watch_value(self) -> None:
        """Tell the screen when typing starts or ends: the footer drops the command keys while one types."""
        if self.editing != self._was_editing:
            self._was_editing = self.editing
            self.refresh_bindings()

    def action_step(self, direction: int, big: bool = False) -> None:
        """Step by one small or big step, clamped to the range: from the typed value if any, else the committed one."""
        start = self.number
        if self.editing:
            start = self._parse_typed()
            if start is None:  # refused, with the message Enter gives: never step the old value silently
                self._select_for_typing()
                return
        size = self.steps.big_step if big else self.steps.step
        self._commit(self.steps.clamp(start + direction * size))
        self._select_for_typing()

    def check_action(self, action: str, parameters: tuple) -> bool | None:
        """Escape is this field's only while it holds typing to discard; otherwise it goes on to the screen,
        so that a dialog whose first field has the focus still closes with one Escape."""
        if action == "revert":
            return self.editing
        return super().check_action(action, parameters)

    def action_revert(self) -> None:
        """Throw away typed text and show the committed value again."""
        self.show_value(self.number)
        self._select_for_typing()

    async def action_submit(self) -> None:
        """Enter: validate the typed text and commit it, or refuse it with a message."""
        self._commit_typed()
        self._select_for_typing()

    def on_blur(self, event: Blur) -> None:
        """Commit typed text when focus leaves: tabbing away should not silently drop it."""
        # Textual runs this before Input's own blur handler, as a subclass's handler.
        self._commit_typed()

    def _select_for_typing(self) -> None:
        """Select the whole text, so that typing replaces the value rather than appending to it."""
        self.select_all()

    def _parse_typed(self) -> float | None:
        """The typed text's value, or None after refusing it with a message (the committed value is shown again)."""
        try:
            return self.steps.parse(self.value)
        except SettingsError as error:
            self.notify(f"{error}. Kept {self.steps.format(self.number)}.", title="Value refused",
                        severity="error", timeout=ROUTINE_SECONDS)
            self.show_value(self.number)
            return None

    def _commit_typed(self) -> None:
        """Commit or refuse what was typed; nothing when nothing was (the field may show the screen's own text,
        such as 'from log', as it loses the focus to being disabled)."""
        if not self.editing:
            return
        if self.value.strip() == self.steps.format(self.number):
            self.show_value(self.number)
            return
        value = self._parse_typed()
        if value is not None:
            self._commit(value)

    def _commit(self, value: float) -> None:
        if value == self.number:
            self.show_value(value)  # tidy the text, e.g. typed "0.5" back to "0.50"
            return
        # The owner shows the value back (show_value) inside this same key handler, so the
        # field and everything the value changes are painted in one frame.
        self._on_commit(self.field, value)
