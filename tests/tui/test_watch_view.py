"""The explorer's watch view (`jointid watch` on a terminal): a scripted watch's refreshes shown as they arrive,
the keys answering while the watch thread runs, q stopping and saving once, and pinned pictures at 80x24 and
120x40 under snapshots/test_watch_view/. The tests wait on the watch's own events, never on pauses counted."""

from __future__ import annotations

import asyncio

import pytest
import pytest_textual_snapshot
from support.printed_numbers import screens_agree
from support.tui_support import THEME
from support.watch_plans import ScriptedPlan, scripted_refreshes
from test_snapshots import COMPACT, WIDE, steady

from jointid.present.watch import convergence_chart, refresh_line
from tui.screens.watch import WatchScreen, new_events
from tui.watch_entry import watch_app
from tui.widgets.convergence import ConvergenceChart
from tui.widgets.readouts import ReadoutPanel

EVENTS = ("connected to 127.0.0.1:5810", "reconnected after a 2.1 s gap (not bridged)")


@pytest.fixture(autouse=True)
def readouts_at_their_precision(monkeypatch):
    """The pictures match when their layout and words are the same and their numbers agree at their printed
    precision (the last digit of a fit's readout differs between CPUs; OPENBLAS_CORETYPE=Prescott shows it)."""
    def matches(self, *, serialized_data, snapshot_data) -> bool:
        return snapshot_data is not None and screens_agree(str(snapshot_data), str(serialized_data))

    monkeypatch.setattr(pytest_textual_snapshot.SVGImageExtension, "matches", matches)


def make_watch_app(plan):
    app = watch_app(plan)
    app.theme = THEME
    return app


async def until(condition, pilot, limit: float = 20.0) -> None:
    """Let the app run until `condition()` holds (each turn waits for the app to be idle, a real event)."""
    async with asyncio.timeout(limit):
        while not condition():
            await pilot.pause()


def test_new_events_are_those_after_the_overlap_of_a_bounded_list():
    assert new_events((), ("a",)) == ("a",)
    assert new_events(("a", "b"), ("a", "b", "c")) == ("c",)
    assert new_events(("a", "b", "c"), ("b", "c", "d", "e")) == ("d", "e")  # the oldest fell off
    assert new_events(("a",), ("a",)) == ()


def test_the_view_shows_the_last_refresh_its_determinations_and_the_source_events():
    refreshes = scripted_refreshes(events=EVENTS)
    plan = ScriptedPlan(refreshes, save_path="arm.csv")

    async def scenario():
        app = make_watch_app(plan)
        async with app.run_test(size=WIDE) as pilot:
            screen = app.screen
            await until(lambda: screen.saved is not None, pilot)
            assert screen.shown is refreshes[-1]
            notes = str(screen.query_one("#watch-notes").render())
            assert "B determined to 8.4 % after 5.1 s" in notes
            status = screen.query_one("#status").shown.plain
            assert "8.0 s, 200 received, 200 fitted" in status and "Wrote 200 samples to arm.csv" in status
            # A reconnection pops up; a connection is said on the status line only.
            assert [notification.message for notification in app._notifications] == [EVENTS[-1]]
            panel = screen.query_one(ReadoutPanel)
            assert panel.items and "0.797765" in " ".join(item.text for item in panel.items)
            assert plan.saves == 1
            await pilot.press("q")
        return app.return_code

    assert asyncio.run(scenario()) in (0, None)


def test_keys_answer_while_watching_and_q_stops_and_saves_once():
    plan = ScriptedPlan(scripted_refreshes(), hold=True, save_path="arm.csv")

    async def scenario():
        app = make_watch_app(plan)
        async with app.run_test(size=COMPACT) as pilot:
            screen = app.screen
            await until(lambda: plan.delivered.is_set() and screen.shown is not None
                        and screen.shown.received == 200, pilot)
            chart = screen.query_one(ConvergenceChart)
            assert chart.data.y_label == "Share of latest"
            await pilot.press("v")  # the watch thread is still waiting on its source
            assert chart.data.y_label == "Error (%)"
            assert chart.data.key() == convergence_chart(screen.shown, "error").key()
            await pilot.press("q")
            await until(lambda: not app.is_running or screen.saved is not None, pilot)
            await pilot.press("q")  # a second press while it saves or after changes nothing more
        return plan

    plan = asyncio.run(scenario())
    assert plan.stopped.is_set() and plan.saves == 1


def test_the_help_lists_the_watch_keys():
    plan = ScriptedPlan(scripted_refreshes(counts=(6, 8)), hold=True)

    async def scenario():
        app = make_watch_app(plan)
        async with app.run_test(size=WIDE) as pilot:
            await pilot.press("question_mark")
            text = app.screen.query_one("Markdown").source
            plan.stop()
            return text

    text = asyncio.run(scenario())
    assert "- `q`: Stop watching, fit what arrived, save it" in text and "## What the view shows" in text
    assert "number field" not in text  # the main screen's controls are not here


def finished(pilot):
    """Before the picture: the scripted watch has ended and its last refresh is shown (no cursor blink)."""
    async def wait():
        steady(pilot)
        await until(lambda: pilot.app.screen.saved is not None, pilot)
    return wait()


@pytest.mark.parametrize("size", [COMPACT, WIDE], ids=lambda size: f"{size[0]}x{size[1]}")
def test_watch_view_snapshot(snap_compare, size):
    plan = ScriptedPlan(scripted_refreshes(events=EVENTS[:1]), save_path="arm.csv")
    assert snap_compare(make_watch_app(plan), terminal_size=size, run_before=finished)


def test_an_undetermined_parameter_shows_the_advice_and_the_error_chart(snap_compare):
    plan = ScriptedPlan(scripted_refreshes(counts=(6, 8, 10, 12)), save_path=None)

    async def before(pilot):
        await finished(pilot)
        await pilot.press("v")

    assert snap_compare(make_watch_app(plan), terminal_size=COMPACT, run_before=before)


def test_text_lines_of_the_same_refreshes_are_one_a_refresh():
    lines = [refresh_line(refresh) for refresh in scripted_refreshes(counts=(6, 8))]
    assert len(lines) == 2 and all("\n" not in line for line in lines)


@pytest.fixture
def sysid_flywheel_csv(tmp_path, monkeypatch):
    """A finished CSV of a flywheel's SysId routine (50 Hz, 40 s: four 10 s tests named in a state column), made
    current: read at once, it is fitted in one block, the same on every run."""
    from support.watched_joints import flywheel

    monkeypatch.chdir(tmp_path)
    run = flywheel(50.0, 40.0)
    tests = ["quasistatic-forward", "quasistatic-reverse", "dynamic-forward", "dynamic-reverse"]
    rows = (f"{t!r},{q!r},{v!r},{tests[min(int(t // 10), 3)]}"
            for t, q, v in zip(run.t.tolist(), run.q.tolist(), run.tau.tolist()))
    (tmp_path / "fly.csv").write_text("t,q,tau,state\n" + "\n".join(rows) + "\n")
    return tmp_path


def test_a_sysid_routine_watched_to_its_end_shows_its_tests_and_gains(snap_compare, sysid_flywheel_csv):
    pytest.importorskip("jointid.studies.watch", reason="livefit's Watcher is not merged into this build yet")
    from jointid.cli import parse
    from jointid.cli.live_plan import open_watch

    args = parse(["watch", "--csv", "fly.csv", "--effort", "voltage", "--mechanism", "simple", "--duration", "39.9",
                  "--refresh", "1", "--save", "fly-watched.csv"])
    plan = open_watch(args, args.refresh)
    assert snap_compare(make_watch_app(plan), terminal_size=WIDE, run_before=finished)
    assert (sysid_flywheel_csv / "fly-watched.csv").exists()
    last = plan.session.last
    assert [name for name, _ in last.tests] == ["quasistatic-forward", "quasistatic-reverse", "dynamic-forward",
                                                "dynamic-reverse"]  # in the order the routine ran them
