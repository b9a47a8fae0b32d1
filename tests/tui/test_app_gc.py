"""The app's garbage-collection tuning lasts for its run only: the process gets its collector back."""

from __future__ import annotations

import asyncio
import gc

import pytest
from support.tui_support import THEME, make_app

from tui.app import JointIdApp


def collector_state() -> tuple[tuple[int, int, int], int, bool]:
    """The process-wide settings the app changes while it runs (it pauses the collector until its first frame)."""
    return gc.get_threshold(), gc.get_freeze_count(), gc.isenabled()


def test_a_run_under_pilot_leaves_the_collector_as_it_was():
    # An explorer run in-process as `jointid` runs it (tests/cli/test_exit_status.py) keeps its freeze for the
    # process's end, and the app only freezes an unfrozen collector: start from one.
    gc.unfreeze()
    before = collector_state()

    async def main():
        app = make_app()
        async with app.run_test(size=(120, 40)) as pilot:
            await pilot.pause()
            assert app.tune_gc
            during = collector_state()
            await pilot.press("right", "r")
            await pilot.pause()
        return during

    during = asyncio.run(main())
    assert during != before  # the tuning was in effect while the app ran
    assert collector_state() == before


def test_the_collector_is_paused_while_the_screen_is_built_and_runs_from_the_first_frame():
    seen = {}

    class Recording(JointIdApp):
        def on_mount(self) -> None:  # after on_load, while the main screen is being built
            seen["building"] = gc.isenabled()

    async def main():
        app = Recording()
        app.theme = THEME
        async with app.run_test(size=(120, 40)) as pilot:
            await pilot.pause()
            seen["ready"] = gc.isenabled()

    assert gc.isenabled()
    asyncio.run(main())
    assert seen == {"building": False, "ready": True}
    assert gc.isenabled()


def test_a_run_that_crashes_leaves_the_collector_as_it_was():
    gc.unfreeze()  # as above: an earlier in-process explorer run in this worker may have left its freeze
    before = collector_state()

    def fail() -> None:
        raise RuntimeError("boom")

    async def main():
        app = make_app()
        async with app.run_test(size=(120, 40)) as pilot:
            await pilot.pause()
            assert collector_state() != before
            app.call_later(fail)
            await pilot.pause()

    with pytest.raises(RuntimeError, match="boom"):
        asyncio.run(main())
    assert collector_state() == before


def test_objects_someone_else_froze_stay_frozen():
    """An embedding program that froze its own heap keeps it frozen; the thresholds still come back."""
    gc.freeze()
    try:
        before = collector_state()

        async def main():
            app = make_app()
            async with app.run_test(size=(80, 24)) as pilot:
                await pilot.pause()

        asyncio.run(main())
        threshold, frozen, enabled = collector_state()
        assert (threshold, enabled) == (before[0], before[2])
        # Still frozen, not unfrozen (0): a frozen object that dies during the run leaves the
        # permanent generation, so after other tests' leftovers the count may drop a little.
        assert 0.9 * before[1] <= frozen <= before[1]
    finally:
        gc.unfreeze()
