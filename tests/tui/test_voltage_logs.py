"""A voltage log in the explorer: volts in the readouts, the chart and its summary, and the gains view (g)."""

from __future__ import annotations

import numpy as np
from support.tui_support import displayed_readouts, make_app, synchronous

from jointid.logs.conventions import LogConventions
from jointid.logs.effort import EffortReading
from jointid.logs.request import LoadRequest
from jointid.model.motors import MotorDrive, motor_named
from tui.screens.gains import GainsScreen
from tui.screens.main import MainScreen
from tui.widgets.charts import TorqueChart

SIZE = (120, 40)


def voltage_log(path):
    """V = kS sgn qd + kG cos q + kV qd + kA qdd of a two-sine motion, with a little noise, as t, q, effort."""
    t = np.linspace(0.0, 12.0, 1201)
    q = 0.3 + 0.9 * np.sin(1.1 * t) + 0.3 * np.sin(2.9 * t + 0.4)
    qd = 0.9 * 1.1 * np.cos(1.1 * t) + 0.3 * 2.9 * np.cos(2.9 * t + 0.4)
    qdd = -0.9 * 1.1**2 * np.sin(1.1 * t) - 0.3 * 2.9**2 * np.sin(2.9 * t + 0.4)
    volts = 0.2 * np.sign(qd) + 0.9 * np.cos(q) + 1.8 * qd + 0.12 * qdd
    volts += np.random.default_rng(1).normal(0.0, 0.02, len(t))
    np.savetxt(path, np.column_stack([t, q, volts]), delimiter=",", header="t,q,effort", comments="", fmt="%.17g")
    return str(path)


@synchronous
async def test_a_voltage_log_shows_volts_and_its_gains(tmp_path):
    app = make_app()
    app.conventions = LogConventions(effort=EffortReading("voltage"), motor=MotorDrive.of(motor_named("NEO"), 1, 60))
    async with app.run_test(size=SIZE) as pilot:
        request = LoadRequest(voltage_log(tmp_path / "arm.csv"), **app.conventions.request_fields())
        pilot.app.screen.start_loading(request)
        await pilot.app.workers.wait_for_complete()
        await pilot.pause()
        screen = next(s for s in app.screen_stack if isinstance(s, MainScreen))
        shown = displayed_readouts(screen)
        assert "Fitted velocity gain (V s/rad)" in shown and "Training RMSE (V)" in shown
        assert "kg m" not in shown and "N m" not in shown
        chart = screen.query(TorqueChart).first()
        assert chart.data.y_label == "Voltage (V)"
        assert " V" in chart.data.summaries[0] and "N m" not in chart.data.summaries[0]
        # The footer has no room for g: the log's note names it, in a line no wider than a torque log's note.
        note = str(screen.query_one("#log-note").render()).splitlines()
        assert note[0] == "From log: c or 1/2/3; g: gains"
        # The command palette lists it too (typing 'gains' there started a tour, which replaced the log).
        assert "Gains" in [command.title for command in app.get_system_commands(screen)]
        await pilot.press("g")
        await pilot.pause()
        assert isinstance(app.screen, GainsScreen)
        text = app.screen.text
        assert "new ArmFeedforward(" in text and "kV (V s/rad)" in text
        assert "Physical parameters behind the gains, through NEO, gear 60:1" in text
        await pilot.press("escape")
        await pilot.pause()
        assert isinstance(app.screen, MainScreen)


@synchronous
async def test_a_torque_log_without_a_motor_has_no_gains_and_says_why(tmp_path):
    from jointid.cli import main

    log = tmp_path / "torque.csv"
    assert main(["simulate", "--samples", "400", "--noise", "0.1", "--out", str(log)]) == 0
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        pilot.app.screen.start_loading(LoadRequest(str(log)))
        await pilot.app.workers.wait_for_complete()
        await pilot.pause()
        await pilot.press("g")
        await pilot.pause()
        assert isinstance(app.screen, MainScreen)
        assert any("needs volts" in notice.message for notice in app._notifications)


@synchronous
async def test_the_ladder_of_a_voltage_log_is_in_volts(tmp_path):
    from tui.screens.ladder import LadderScreen

    app = make_app()
    app.conventions = LogConventions(effort=EffortReading("voltage"))
    async with app.run_test(size=SIZE) as pilot:
        pilot.app.screen.start_loading(LoadRequest(voltage_log(tmp_path / "arm.csv"),
                                                   **app.conventions.request_fields()))
        await pilot.app.workers.wait_for_complete()
        await pilot.pause()
        await pilot.press("l")
        await pilot.pause()
        assert isinstance(app.screen, LadderScreen)
        assert all(row.model.effort.unit == "V" for row in app.screen.comparison.rows)
        assert app.screen.comparison.row("coulomb").model.names == ("kA", "kG", "kV", "kS")


@synchronous
async def test_the_open_dialog_reads_a_log_as_voltage_when_asked(tmp_path):
    from textual.widgets import RadioSet

    from tui.screens.open_log import OpenLogScreen

    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await pilot.press("ctrl+o")
        dialog = app.screen
        assert isinstance(dialog, OpenLogScreen)
        assert dialog.request(str(tmp_path / "x.csv")).effort.kind == "torque"
        assert not dialog.query_one("#effort-current").disabled
        assert dialog.query_one("#open-kt").disabled  # a current's gear, kt and efficiency only once it is chosen
        dialog.query_one("#effort-voltage").value = True
        await pilot.pause()
        assert dialog.query_one("#open-effort", RadioSet).pressed_button.id == "effort-voltage"
        assert dialog.request(str(tmp_path / "x.csv")).effort.kind == "voltage"


@synchronous
async def test_at_80_columns_end_and_home_reach_the_ends_of_a_wide_gains_line(tmp_path):
    """The C++ constructor is wider than 80 columns: End shows its end and Home its start (Right moves one column,
    and End scrolled down instead)."""
    from tui.widgets.wide_scroll import WideScroll

    app = make_app()
    app.conventions = LogConventions(effort=EffortReading("voltage"))
    async with app.run_test(size=(80, 24)) as pilot:
        pilot.app.screen.start_loading(LoadRequest(voltage_log(tmp_path / "arm.csv"), **app.conventions.request_fields()))
        await pilot.app.workers.wait_for_complete()
        await pilot.pause()
        await pilot.press("g")
        await pilot.pause()
        assert isinstance(app.screen, GainsScreen)
        wide = [scroll for scroll in app.screen.query(WideScroll) if scroll.max_scroll_x > 0]
        assert wide  # at 80 columns the constructor lines do not fit
        scroll = wide[-1]
        scroll.focus()
        await pilot.press("end")
        await pilot.pause()
        assert scroll.scroll_x == scroll.max_scroll_x
        await pilot.press("home")
        await pilot.pause()
        assert scroll.scroll_x == 0
