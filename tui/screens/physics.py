"""The physics dialog: give the synthetic joint missing physics, choose the fitted model, constrain the fit.

Every change applies at once (the main screen refits beside the dialog), so a
student can step the Coulomb friction and watch the plain model's damping grow:
the dialog stands over the charts and leaves the side panel, with its readouts, in view.
The dialog holds no setting of its own: it shows the main screen's settings and
reports each change through the main screen's callbacks, as every control does.
"""

from __future__ import annotations

from typing import Callable

from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical
from textual.screen import ModalScreen
from textual.widgets import Static

from jointid.options import LADDER
from jointid.synthetic.settings import Settings

from ..ranges import PHYSICS_LABELS, PHYSICS_RANGES
from ..sizes import size_classes
from ..widgets.direct_controls import ChoiceList
from ..widgets.footer import KeyFooter
from ..widgets.stepper import Stepper

CONSTRAINT_OPTIONS = (("constraint-off", "Unconstrained least squares"),
                      ("constraint-on", "Sign rules: I, h, B, Fc ≥ 0"))
"""The fit's two kinds, as the constraint list shows them."""


class PhysicsScreen(ModalScreen[None]):
    """Missing physics of the synthetic joint, the fitted model and the constraint; Escape closes."""

    DEFAULT_CSS = """
    PhysicsScreen {
        /* Undimmed: the readouts beside the dialog are what its changes are watched on. */
        background: transparent;
    }
    PhysicsScreen > #physics {
        width: 1fr;
        height: auto;
        max-height: 100%;
        background: $surface;
        border: round $primary;
        border-title-align: left;
        padding: 0 1;
    }
    PhysicsScreen .field {
        height: 1;
    }
    PhysicsScreen .field--label {
        width: 1fr;
    }
    PhysicsScreen Stepper {
        width: 10;
    }
    PhysicsScreen .physics--heading {
        margin-top: 1;
        text-style: bold;
    }
    PhysicsScreen .physics--heading.-first {
        margin-top: 0;
    }
    PhysicsScreen .physics--hint {
        color: $text-muted;
    }
    """

    BINDINGS = [
        Binding("escape", "close", "Close", tooltip="Back to the explorer with these settings"),
        Binding("p", "close", "Close", show=False),
    ]

    def __init__(self, settings: Settings, on_change: Callable[[str, object], None]) -> None:
        """Create the dialog.

        Args:
            settings: The main screen's settings, shown first.
            on_change: Called with a setting's name and its new value (the main screen refits).
        """
        super().__init__()
        self.settings = settings
        self._on_change = on_change

    def compose(self) -> ComposeResult:
        """Three number fields for the true joint, the model list, the constraint list, a hint."""
        self.update_classes(size_classes(*self.app.size))  # before styling, as the main screen does
        with Vertical(id="physics") as box:
            box.border_title = "Physics: true joint, fitted model"
            yield Static("The true joint also has (0: none)", classes="physics--heading -first")
            for steps in PHYSICS_RANGES:
                with Horizontal(classes="field"):
                    yield Static(PHYSICS_LABELS[steps.field], classes="field--label", markup=False)
                    yield Stepper(steps, getattr(self.settings, steps.field), on_commit=self._on_change,
                                  id=steps.field)
            yield Static("Fitted model", classes="physics--heading")
            yield ChoiceList([(f"model-{name}", name) for name in LADDER], on_choose=self.choose_model, id="model")
            yield Static("Fit", classes="physics--heading")
            yield ChoiceList(list(CONSTRAINT_OPTIONS), on_choose=self.choose_constraint, id="constraint")
            yield Static("←/→ step a field, Up/Down and Enter choose; changes apply at once and show "
                         "in the readouts beside. l in the explorer compares every model.", classes="physics--hint")
        yield KeyFooter()

    def on_mount(self) -> None:
        """Show the current model and constraint, and focus the first field."""
        self.show(self.settings)
        self.query_one(Stepper).focus()

    def on_resize(self) -> None:
        """The main screen's size classes, so app.tcss leaves the side panel's width free as it sizes the panel."""
        self.update_classes(size_classes(*self.size))

    def show(self, settings: Settings) -> None:
        """Display settings the main screen now holds (after a change, or a value it refused)."""
        self.settings = settings
        for steps in PHYSICS_RANGES:
            self.query_one(f"#{steps.field}", Stepper).show_value(getattr(settings, steps.field))
        models = self.query_one("#model", ChoiceList)
        models.show_pressed(f"model-{settings.model}" if settings.model in LADDER else "")
        self.query_one("#constraint", ChoiceList).show_pressed(
            "constraint-on" if settings.constrained else "constraint-off")

    def choose_model(self, option: str) -> None:
        """The model list's choice."""
        self._on_change("model", option.removeprefix("model-"))

    def choose_constraint(self, option: str) -> None:
        """The constraint list's choice."""
        self._on_change("constrained", option == "constraint-on")

    def action_close(self) -> None:
        """Back to the explorer."""
        self.dismiss(None)
