"""What the explorer says when a key or a value cannot do what was asked (issue 24, item 10): no internal names,
no silent keys, and Reset back to the lesson as the tour's first stop is.

Keys are delivered as one batch (support.bursts.send_burst); waits are on the app's own messages.
"""

from __future__ import annotations

from dataclasses import replace

from support.bursts import send_burst, with_app

from jointid.synthetic.settings import DEFAULT_SETTINGS
from tui.notices import ROUTINE_SECONDS
from tui.palette import PHYSICS_STOPS
from tui.screens.physics import PhysicsScreen
from tui.widgets.stepper import Stepper


def titled(app, title: str) -> list:
    return [n for n in app._notifications if n.title == title]


@with_app
async def test_a_refused_physics_value_names_the_field_as_the_dialog_does(pilot, app, watch):
    send_burst(app, "p")
    await watch.until(app, lambda: isinstance(app.screen, PhysicsScreen), "the physics dialog")
    field = app.screen.query_one("#true_coulomb", Stepper)
    await watch.until(app, lambda: field.has_focus, "the first field's focus")
    send_burst(app, "-", "1", "enter")
    await watch.until(app, lambda: titled(app, "Value refused"), "the refusal")
    message = titled(app, "Value refused")[0].message
    assert message.startswith("Coulomb friction FC must be a number from 0.00 to ") and "true_coulomb" not in message


@with_app
async def test_4_before_a_design_says_how_to_get_one(pilot, app, watch):
    screen = app.screen
    send_burst(app, "4")
    await watch.until(app, lambda: app._notifications, "a notification")
    [note] = app._notifications
    assert "press d to design one, then t to train on it" in note.message
    assert note.severity == "warning" and note.timeout == ROUTINE_SECONDS
    assert screen.settings == DEFAULT_SETTINGS


@with_app
async def test_r_goes_back_to_the_lessons_joint_and_fit_and_says_so(pilot, app, watch):
    screen = app.screen
    _, coulomb_model, _ = PHYSICS_STOPS[1]  # Coulomb friction under the Coulomb model
    screen.apply_settings(coulomb_model)
    send_burst(app, "k", "r")  # constrained too
    await watch.until(app, lambda: titled(app, "Reset"), "Reset's note")
    assert screen.settings == DEFAULT_SETTINGS
    assert titled(app, "Reset")[0].message == ("Back to the lesson's joint and fit: no missing physics, the plain "
                                               "model, an unconstrained fit (p changes them).")
    assert str(screen.query_one("#known").render()).endswith("q from +x, counter-clockwise.")  # no "It also has"


@with_app
async def test_r_on_the_lessons_joint_says_nothing(pilot, app, watch):
    screen = app.screen
    screen.apply_settings(replace(DEFAULT_SETTINGS, motion="slow", noise=0.2))
    send_burst(app, "r")
    await watch.until(app, lambda: screen.settings == DEFAULT_SETTINGS, "the reset")
    app.notify("after the reset")  # handled after anything the reset said
    await watch.until(app, lambda: app._notifications, "a notification")
    assert [n.message for n in app._notifications] == ["after the reset"]
