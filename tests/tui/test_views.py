"""Pilot tests of the analysis views (seed sweep, cross-excitation, residuals) and the precision readouts."""

from __future__ import annotations

import time

import numpy as np
import pytest
from support.tui_support import CANONICAL_STATES, READOUTS_DIR, run_app

from jointid.estimation.residuals import AXES, AXIS_NOTES, residual_data
from jointid.present.tables import matrix_table, sweep_message
from jointid.present.tables import sweep_table as statistics_table
from jointid.studies.cross_excitation import cross_excitation
from jointid.studies.experiment import run_experiment
from jointid.studies.sweep import SweepCancelled, run_sweep
from tui.screens import sweep as sweep_screen
from tui.screens.main import MainScreen
from tui.screens.matrix import MatrixScreen
from tui.screens.residuals import AXIS_KEYS, ResidualScreen
from tui.screens.sweep import SweepScreen
from tui.widgets.readouts import ReadoutPanel
from tui.widgets.small_plots import SmallPlot
from tui.widgets.stepper import Stepper

SLOW = CANONICAL_STATES["slow_0.20"]
HOLDS = CANONICAL_STATES["holds"]
SIZES = [(80, 24), (120, 40)]


def run(scenario, settings=SLOW, size=(120, 40)):
    """Run an async scenario(pilot, app) against a fresh app (slow motion at noise 0.20 unless told)."""
    return run_app(scenario, settings, size)


async def open_view(pilot, key: str):
    """Press a view's key, let any sweep finish, and return the new screen."""
    await pilot.press(key)
    await pilot.app.workers.wait_for_complete()
    await pilot.pause()
    return pilot.app.screen


def text(screen, selector: str) -> str:
    """The plain text a Static displays."""
    return str(screen.query_one(selector).render())


# --- precision readouts -------------------------------------------------------------


def panel_text(screen) -> str:
    panel = screen.query_one(ReadoutPanel)
    return "\n".join(line.plain for line in panel.lines(200))


def test_readouts_show_standard_errors_and_verdicts_from_the_core():
    async def scenario(pilot, app):
        return panel_text(app.screen)

    shown = run(scenario)
    uncertainty = run_experiment(SLOW).uncertainty
    for error, verdict in zip(uncertainty.verdict_std_error, uncertainty.verdicts):
        assert f"± {error:.6f}  {verdict}" in shown
    assert "± 5.425077  not determined" in shown and "± 1.013808  not determined" in shown
    assert "Condition number           3.78" in shown
    assert "modest does not mean accurate" in shown


def test_holds_readouts_name_the_identifiable_subset_and_why_the_rest_is_free():
    async def scenario(pilot, app):
        return panel_text(app.screen)

    shown = run(scenario, HOLDS)
    assert "h = 0.400000, determined alone" in shown
    assert "not determined: no acceleration" in shown and "not determined: no velocity" in shown
    assert "Condition number           infinite" in shown


@pytest.mark.parametrize("state", sorted(CANONICAL_STATES))
def test_every_readout_fits_80x24_without_scrolling(state):
    async def scenario(pilot, app):
        side, panel = app.screen.query_one("#side"), app.screen.query_one(ReadoutPanel)
        return side.max_scroll_y, panel.region.bottom <= side.region.bottom, panel.compact

    assert run(scenario, CANONICAL_STATES[state], size=(80, 24)) == (0, True, True)


# --- keys, bindings, palette --------------------------------------------------------


@pytest.mark.parametrize("key, screen_type", [("s", SweepScreen), ("m", MatrixScreen), ("e", ResidualScreen)])
@pytest.mark.parametrize("size", SIZES)
def test_each_view_opens_by_key_and_escape_returns(key, screen_type, size):
    async def scenario(pilot, app):
        view = await open_view(pilot, key)
        opened = isinstance(view, screen_type)
        await pilot.press("escape")
        await pilot.pause()
        return opened, isinstance(app.screen, MainScreen)

    assert run(scenario, size=size) == (True, True)


@pytest.mark.parametrize("key", ["s", "m", "e"])
def test_views_open_for_a_rank_deficient_motion(key):
    async def scenario(pilot, app):
        view = await open_view(pilot, key)
        return type(view).__name__

    assert run(scenario, HOLDS, size=(80, 24)) != "MainScreen"


def test_view_keys_are_bindings_with_descriptions_in_the_palette():
    async def scenario(pilot, app):
        return {command.title for command in app.get_system_commands(app.screen)}

    titles = run(scenario)
    assert {"Sweep", "Matrix", "Residuals"} <= titles
    descriptions = {}
    for binding in MainScreen.BINDINGS:  # each key's first binding (the others explain why it is off)
        descriptions.setdefault(binding.key, binding.description)
    assert descriptions["s"] and descriptions["m"] and descriptions["e"]


@pytest.mark.parametrize("key, titles", [("s", {"Cancel / back", "Cancel", "Run again"}),
                                         ("m", {"Back"}), ("e", {"Back", "t", "q", "qd", "qdd"})])
def test_view_keys_are_in_the_palette_too(key, titles):
    async def scenario(pilot, app):
        view = await open_view(pilot, key)
        return {command.title for command in app.get_system_commands(view)}

    assert titles <= run(scenario)


def test_help_lists_the_view_keys():
    from tui.screens.help import help_markdown

    help_text = help_markdown(MainScreen.BINDINGS)
    for phrase in ("`s`", "`m`", "`e`", "Seed sweep", "Cross-excitation", "Residuals"):
        assert phrase in help_text


# --- seed sweep ---------------------------------------------------------------------


def test_sweep_view_shows_the_core_statistics():
    async def scenario(pilot, app):
        view = await open_view(pilot, "s")
        return view.result, text(view, "#sweep-table"), text(view, "#sweep-summary")

    result, table, summary = run(scenario)
    expected = run_sweep(SLOW, 1000)
    assert result.seed_count == 1000 and int(result.seeds[0]) == SLOW.seed
    np.testing.assert_array_equal(result.estimates, expected.estimates)
    assert table == statistics_table(expected)
    assert summary.startswith(sweep_message(expected))
    assert "std (expected)     5.425077" in table


def test_sweep_seed_count_can_be_typed_and_is_validated():
    async def scenario(pilot, app):
        view = await open_view(pilot, "s")
        field = view.query_one(Stepper)
        field.value = "50"
        await pilot.press("enter")
        await app.workers.wait_for_complete()
        await pilot.pause()
        first = view.result.seed_count
        field.value = "0"
        await pilot.press("enter")
        await pilot.pause()
        return first, field.number, view.result.seed_count

    assert run(scenario) == (50, 50, 50)


def test_sweep_seed_count_steps_with_the_arrow_keys():
    async def scenario(pilot, app):
        view = await open_view(pilot, "s")
        await pilot.press("right")
        await app.workers.wait_for_complete()
        await pilot.pause()
        return view.result.seed_count

    assert run(scenario) == 1100


def test_sweep_can_be_cancelled_without_freezing(monkeypatch):
    """A sweep that would run forever stops on Escape; the view stays, a second Escape leaves."""

    def endless(settings, seed_count, *, chunk_size=None, progress=None, cancelled=None):
        done = 0
        while not cancelled():
            done = min(done + 1, seed_count)
            progress(done, seed_count)
            time.sleep(0.005)
        raise SweepCancelled("cancelled")

    monkeypatch.setattr(sweep_screen, "run_sweep", endless)

    async def scenario(pilot, app):
        await pilot.press("s")
        await pilot.pause(0.05)
        view = app.screen
        running = view.running
        await pilot.press("escape")
        await app.workers.wait_for_complete()
        await pilot.pause()
        state = (running, view.running, view.result, text(view, "#sweep-state"), app.screen is view)
        await pilot.press("escape")
        await pilot.pause()
        return state, isinstance(app.screen, MainScreen)

    state, back = run(scenario)
    assert state == (True, False, None, "cancelled", True)
    assert back


def test_sweep_histograms_mark_the_true_values():
    async def scenario(pilot, app):
        view = await open_view(pilot, "s")
        return [plot.data.true_value for plot in view.query(SmallPlot)]

    assert run(scenario) == [0.8, 0.4, 0.15]


# --- cross-excitation ---------------------------------------------------------------


def test_matrix_view_shows_the_core_table_with_training_entries_marked():
    async def scenario(pilot, app):
        view = await open_view(pilot, "m")
        return text(view, "#matrix-table"), text(view, "#matrix-notes")

    table, notes = run(scenario)
    core = cross_excitation(SLOW)
    assert table == matrix_table(core)
    rows = table.splitlines()
    assert "0.017032 *" in rows[1] and "0.021961 *" in rows[2] and "2.261865  " in rows[2] + "  "
    assert rows[3].count("unavailable") == 3
    assert "training data" in notes and "held-out" not in table
    for row in core.rows:
        for cell in row.cells:
            if cell.rmse is not None:
                assert f"{cell.rmse:.6f}" + (" *" if cell.is_training_data else "") in table


# --- residuals ----------------------------------------------------------------------


@pytest.mark.parametrize("settings", [SLOW, HOLDS])
def test_residual_view_switches_axes_by_key(settings):
    async def scenario(pilot, app):
        view = await open_view(pilot, "e")
        shown = {}
        for axis in AXES:
            await pilot.press(AXIS_KEYS[axis])
            await pilot.pause()
            plot = view.query_one(SmallPlot).data
            shown[axis] = (plot.x, plot.y, text(view, "#residual-note"))
        return shown

    shown = run(scenario, settings)
    data = residual_data(run_experiment(settings))
    for axis in AXES:
        x, y, note = shown[axis]
        np.testing.assert_array_equal(x, data.axes[axis])
        np.testing.assert_array_equal(y, data.residuals)
        assert note.endswith(AXIS_NOTES[axis])


# --- pinned view texts --------------------------------------------------------------

VIEW_READOUTS_DIR = READOUTS_DIR / "views"
"""Pinned texts of the analysis views (a subfolder: the main readouts' own check globs only *.txt)."""

VIEW_PINS = {
    "sweep_slow_0.20": (SLOW, "s", ("#sweep-title", "#sweep-table", "#sweep-summary")),
    "sweep_rich_0.20": (CANONICAL_STATES["rich_0.20"], "s", ("#sweep-title", "#sweep-table", "#sweep-summary")),
    "sweep_holds": (HOLDS, "s", ("#sweep-title", "#sweep-table", "#sweep-summary")),
    "matrix_slow_0.20": (SLOW, "m", ("#matrix-title", "#matrix-table", "#matrix-notes")),
    "residuals_slow_0.20": (SLOW, "e", ("#residual-title", "#residual-summary", "#residual-note")),
}
"""Pinned view texts: settings, the view's key, and the Statics read off it."""


def displayed_view_text(name: str) -> str:
    """The pinned Statics of a view, as displayed at 120x40, one block each."""
    settings, key, selectors = VIEW_PINS[name]

    async def scenario(pilot, app):
        view = await open_view(pilot, key)
        return "\n\n".join(text(view, selector) for selector in selectors) + "\n"

    return run(scenario, settings)


@pytest.mark.parametrize("name", sorted(VIEW_PINS))
def test_view_texts_match_pinned(name):
    """The views show exactly the pinned numbers; a change is a readable diff."""
    pinned = (VIEW_READOUTS_DIR / f"{name}.txt").read_text(encoding="utf-8")
    assert displayed_view_text(name) == pinned


def test_every_pinned_view_file_belongs_to_a_view():
    assert {path.stem for path in VIEW_READOUTS_DIR.glob("*.txt")} == set(VIEW_PINS)


if __name__ == "__main__":
    # Regenerate on purpose:  .venv/bin/python tests/tui/test_views.py  (then review the diff)
    VIEW_READOUTS_DIR.mkdir(parents=True, exist_ok=True)
    for view_name in VIEW_PINS:
        (VIEW_READOUTS_DIR / f"{view_name}.txt").write_text(displayed_view_text(view_name), encoding="utf-8")
        print(f"wrote views/{view_name}.txt")
