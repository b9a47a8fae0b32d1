"""Several runs of one joint in the explorer: opened together, one more added with Ctrl+O's "Another run", each
run's own fit on the main screen, and the per-run table with the pooled fit in its own view (u)."""

from __future__ import annotations

import json

import pytest
from support.tui_support import make_app, synchronous

from jointid.cli import main
from jointid.logs.request import HELDOUT, RUN, LoadRequest, load_joint_log
from jointid.model.terms import model_named
from jointid.options import LOG_MODEL
from jointid.present.readouts import readouts
from jointid.studies.runs import fit_runs
from tui.widgets.readouts import ReadoutPanel

SIZE = (120, 40)


@pytest.fixture
def runs(tmp_path):
    """Three noisy runs of the lesson's joint on the rich, slow and test motions, written by `jointid simulate`."""
    paths = []
    for k, motion in enumerate(("rich", "slow", "test")):
        path = tmp_path / f"run{k + 1}.csv"
        assert main(["simulate", "--motion", motion, "--noise", "0.05", "--seed", str(k), "--samples", "800",
                     "--out", str(path)]) == 0
        paths.append(str(path))
    return paths


async def load(pilot, path, role):
    """Load a file as the Ctrl+O dialog would, and wait until the worker's outcome is shown."""
    pilot.app.screen.start_loading(LoadRequest(path, role))
    await pilot.app.workers.wait_for_complete()
    await pilot.pause()


@synchronous
async def test_runs_opened_together_show_each_run_and_the_pooled_table(runs):
    pooled = fit_runs([load_joint_log(LoadRequest(path)) for path in runs[:2]], model_named(LOG_MODEL))
    app = make_app(logs=pooled)
    async with app.run_test(size=SIZE) as pilot:
        screen = app.screen
        assert screen.logs is pooled.runs[0]
        note = str(screen.query_one("#log-note").render())
        assert "Run 1 of 2 · u: every run, pooled I" in note
        assert screen.query_one(ReadoutPanel).items == readouts(pooled.runs[0].result)
        await pilot.press("u")
        await pilot.pause()
        assert type(app.screen).__name__ == "RunsScreen"
        shown = "\n".join(str(widget.render()) for widget in app.screen.query("Static"))
        assert "run1.csv" in shown and "run2.csv" in shown and "pooled" in shown
        await pilot.press("2")  # the second run's own fit on the main screen
        await pilot.pause()
        assert app.screen is screen and screen.logs is pooled.runs[1]
        assert screen.query_one(ReadoutPanel).items == readouts(pooled.runs[1].result)
        await pilot.press("u", "9")  # no ninth run: nothing happens, the view stays
        await pilot.pause()
        assert type(app.screen).__name__ == "RunsScreen"
        await pilot.press("escape")
        await pilot.pause()
        # The export is the pooled runs' document, as `jointid fit --csv A --csv B --json` prints it.
        stem, document = screen.export_content()
        assert stem == "run1-runs-fit" and [run["name"] for run in document["runs"]] == ["run1.csv", "run2.csv"]
        assert document["pooled"]["estimate"]["I"] == pytest.approx(pooled.params["I"], rel=1e-12)
        json.dumps(document)


@synchronous
async def test_another_run_is_pooled_with_the_log_shown_and_a_heldout_log_is_refused_with_runs(runs):
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await load(pilot, runs[2], RUN)  # no training log yet: said, nothing changes
        screen = app.screen
        assert screen.logs is None and screen.runs is None
        assert "needs a training log first" in list(app._notifications)[-1].message
        await load(pilot, runs[0], "training")
        await load(pilot, runs[1], RUN)
        await load(pilot, runs[2], RUN)
        assert screen.runs is not None and screen.logs is screen.runs.runs[2]
        # Fitted with the explorer's model (the lesson's, opened from the synthetic experiment).
        expected = fit_runs([load_joint_log(LoadRequest(path)) for path in runs], screen.settings.joint_model)
        for name in expected.shared:
            assert screen.runs.params[name] == pytest.approx(expected.params[name], rel=1e-9)
        assert "Run 3 of 3" in str(screen.query_one("#log-note").render())
        assert screen.query_one("#motion").render().plain.splitlines()[-1].endswith(" Run 3: run3.csv ")
        # The model changes: every run is refitted and pooled again, the run shown stays.
        screen.change_fit("model", LOG_MODEL)
        await app.workers.wait_for_complete()
        await pilot.pause()
        assert [run.result.model.name for run in screen.runs.runs] == [LOG_MODEL] * 3
        assert screen.logs is screen.runs.runs[2]
        # A held-out log beside several runs is refused (each run is predicted by the others); a training log
        # replaces them.
        await load(pilot, runs[0], HELDOUT)
        assert len(screen.runs.runs) == 3 and "no held-out log" in list(app._notifications)[-1].message
        await load(pilot, runs[1], "training")
        assert screen.runs is None and screen.logs.name == "run2.csv"
        await load(pilot, runs[0], RUN)
        # c leaves the runs with the log.
        await pilot.press("c")
        await pilot.pause()
        assert screen.logs is None and screen.runs is None


@synchronous
async def test_the_open_dialog_offers_another_run_only_beside_a_log(runs):
    from tui.screens.open_log import OpenLogScreen

    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await pilot.press("ctrl+o")
        await pilot.pause()
        assert isinstance(app.screen, OpenLogScreen)
        assert app.screen.query_one(f"#role-{RUN}").disabled
        await pilot.press("escape")
        await load(pilot, runs[0], "training")
        await load(pilot, runs[1], RUN)
        await pilot.press("ctrl+o")
        await pilot.pause()
        assert not app.screen.query_one(f"#role-{RUN}").disabled
        assert app.screen.query_one(f"#role-{HELDOUT}").disabled  # each run is predicted by the others instead


@synchronous
async def test_at_80_columns_the_runs_table_scrolls_sideways_from_the_keyboard(runs):
    pooled = fit_runs([load_joint_log(LoadRequest(path)) for path in runs], model_named(LOG_MODEL))
    app = make_app(logs=pooled)
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.press("u")
        await pilot.pause()
        table = app.screen.query_one("#runs-table")
        assert table.max_scroll_x > 0  # the table is wider than the view: its columns are not wrapped
        await pilot.press("tab", "right", "right")
        await pilot.pause()
        assert app.screen.focused is table and table.scroll_x > 0
