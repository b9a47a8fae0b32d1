"""The explorer opens WPILib data logs: Ctrl+O on a SysId log shows its tests as runs, other logs ask for entries."""

from __future__ import annotations

import pytest

pytest.importorskip("wpiutil")

import wpiutil  # noqa: E402
from support.datalog_bytes import damaged_logs  # noqa: E402
from support.sysid_arm import TESTS, Routine, routine_samples, write_routine_log  # noqa: E402
from support.tui_support import make_app  # noqa: E402
from test_logs import SIZE, main_screen, synchronous  # noqa: E402
from textual.widgets import Input, OptionList  # noqa: E402

from jointid.logs.conventions import EntryMap  # noqa: E402
from jointid.logs.request import LoadRequest, load_joint_logs  # noqa: E402
from jointid.studies.sysid import SYSID_MODEL, fit_sysid_runs  # noqa: E402
from tui.screens.main import MainScreen  # noqa: E402
from tui.screens.wpilog_entry import WpilogEntryScreen  # noqa: E402


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("tui-wpilog")
    routine = Routine(quasistatic=2.5, dynamic=1.0)
    sysid = write_routine_log(folder / "arm.wpilog", routine_samples(routine), routine)
    plain = folder / "robot.wpilog"
    writer = wpiutil.DataLogWriter(str(plain))
    angle = wpiutil.log.DoubleLogEntry(writer, "/Arm/Angle", 1)  # no unit: the picker asks for it
    volts = wpiutil.log.DoubleLogEntry(writer, "/Arm/Volts", "Volt", 1)
    name = wpiutil.log.StringLogEntry(writer, "/Event/Name", 1)
    name.append("practice", 10)
    samples = routine_samples(routine)[2]  # the dynamic-forward test alone
    for k, t in enumerate(samples.t):
        stamp = 1_000_000 + int(t * 1e6)
        angle.append(float(samples.q[k] * 180 / 3.141592653589793), stamp)
        volts.append(float(samples.voltage[k]), stamp + 20)
    writer.flush()
    writer.stop()
    broken = folder / "broken.wpilog"
    data = sysid.read_bytes()
    broken.write_bytes(data[: len(data) // 3 + 3])
    damaged = folder / "damaged.wpilog"
    damaged.write_bytes(damaged_logs()["entry-name-not-utf8"][0])
    return {"sysid": sysid, "plain": plain, "broken": broken, "damaged": damaged}


async def settle(pilot, until=None):
    """Wait for the picker's survey and the log's load (the folder tree keeps a worker running for ever)."""
    for _ in range(500):
        busy = [w for w in pilot.app.workers if w.group in ("wpilog-survey", "log-load") and not w.is_finished]
        if not busy and (until is None or until()):
            break
        await pilot.pause(0.02)
    await pilot.pause()


async def open_path(pilot, path):
    await pilot.press("ctrl+o")
    pilot.app.screen.query_one("#open-path", Input).value = str(path)
    await pilot.press("enter")


@synchronous
async def test_ctrl_o_on_a_sysid_log_shows_its_four_tests_as_runs(logs):
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await open_path(pilot, logs["sysid"])
        await settle(pilot, lambda: isinstance(app.screen, MainScreen) and app.screen.runs is not None)
        screen = main_screen(app)
        assert isinstance(app.screen, MainScreen) and screen.runs is not None
        assert [run.name for run in screen.runs.runs] == [test for test, _ in TESTS]
        assert screen.logs is screen.runs.runs[0] and screen.settings.model == SYSID_MODEL
        estimate = dict(screen.runs.params)
        notes = [n.message for n in app._notifications]
        await pilot.press("u")  # the runs view lists every test
        await pilot.pause()
    # The pooled estimate does not depend on the sensitivity check's refits, which are skipped here.
    expected = fit_sysid_runs(load_joint_logs(LoadRequest(str(logs["sysid"]), wpilog=True, window=None)),
                              sensitivity=False)
    assert estimate == pytest.approx(dict(expected.params), rel=1e-9)
    assert any("4 SysId tests" in note for note in notes)


@synchronous
async def test_ctrl_r_on_a_sysid_log_writes_its_pooled_gains_and_constructor(logs, tmp_path, monkeypatch):
    """The explorer's report of a SysId log holds the gains `jointid report --gains wpilib` gives (it had only the
    runs table and each test's own fit, so not what a team came for)."""
    from jointid.present.gains import gains_text
    from jointid.studies.gains import arm_gains

    monkeypatch.chdir(tmp_path)
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await open_path(pilot, logs["sysid"])
        await settle(pilot, lambda: isinstance(app.screen, MainScreen) and app.screen.runs is not None)
        runs = main_screen(app).runs
        await pilot.press("ctrl+r")
        for _ in range(2000):  # the page is drawn in a worker: wait for its file
            if list(tmp_path.glob("*.html")):
                break
            await pilot.pause(0.02)
    pages = list(tmp_path.glob("*.html"))
    assert len(pages) == 1
    constructor = next(line for line in gains_text(arm_gains(runs)).splitlines() if line.startswith("Java:"))
    assert constructor.removeprefix("Java:").strip() in pages[0].read_text()


@synchronous
async def test_another_log_asks_for_the_angle_the_effort_and_the_unit(logs, monkeypatch):
    import jointid.logs.wpilog as wpilog

    monkeypatch.setattr(wpilog, "PROGRESS_RECORDS", 64)  # the survey reports its progress to the picker often
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await open_path(pilot, logs["plain"])
        await settle(pilot, lambda: isinstance(app.screen, WpilogEntryScreen)
                     and app.screen.query_one(OptionList).option_count)
        options = app.screen.query_one(OptionList)
        prompts = [str(options.get_option_at_index(i).prompt) for i in range(options.option_count)]
        assert prompts[0].startswith("/Arm/Angle: double, ") and prompts[1].startswith("/Arm/Volts: double, ")
        assert len(prompts) == 2  # the string entry is no angle
        await pilot.press("enter")  # /Arm/Angle
        await pilot.pause()
        assert options.option_count == 1
        await pilot.press("enter")  # /Arm/Volts
        await pilot.pause()
        units = [str(options.get_option_at_index(i).prompt) for i in range(options.option_count)]
        assert units == ["radians", "rotations", "degrees"]
        await pilot.press("down", "down", "enter")  # degrees
        await settle(pilot, lambda: isinstance(app.screen, MainScreen) and app.screen.logs is not None)
        screen = main_screen(app)
        assert screen.logs is not None and screen.runs is None
        q = screen.logs.training.source.columns["q"]
    entries = EntryMap((("q", "/Arm/Angle"), ("tau", "/Arm/Volts")))
    (expected,) = load_joint_logs(LoadRequest(str(logs["plain"]), wpilog=True, entries=entries, units="degrees"))
    assert list(q) == list(expected.source.columns["q"])


@pytest.mark.parametrize(("case", "expected"), [("broken", "cut short or damaged"), ("damaged", "is not UTF-8")])
@synchronous
async def test_a_broken_log_is_one_notification_and_nothing_changes(logs, case, expected):
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await open_path(pilot, logs[case])
        await settle(pilot, lambda: not isinstance(app.screen, WpilogEntryScreen))
        assert not isinstance(app.screen, WpilogEntryScreen)
        (note,) = app._notifications
        assert note.severity == "error" and expected in note.message
        await pilot.press("escape")
        assert isinstance(app.screen, MainScreen) and app.screen.logs is None


@synchronous
async def test_an_elevators_readouts_give_its_speed_in_metres_per_second(tmp_path):
    """A log whose position is a length shows the motion's RMS per metre, as the command line's text does."""
    from support.sysid_mechanisms import ELEVATOR, write_mechanism_log
    from tui.widgets.readouts import ReadoutPanel

    path = write_mechanism_log(tmp_path / "elevator.wpilog", ELEVATOR)
    app = make_app()
    async with app.run_test(size=SIZE) as pilot:
        await open_path(pilot, path)
        await settle(pilot, lambda: isinstance(app.screen, MainScreen) and app.screen.runs is not None)
        labels = {item.label for item in app.screen.query_one(ReadoutPanel).items}
    assert {"Speed RMS (m/s)", "Acceleration RMS (m/s²)"} <= labels, labels
