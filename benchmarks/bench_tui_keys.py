"""Key press to fully updated explorer screen, headless at 120x40, over 200 presses.

Run: .venv/bin/python benchmarks/bench_tui_keys.py

The app runs headless under Pilot (`run_test`), which also focuses each control
in turn. The 200 presses across every control (noise, samples and seed fields
with small and big steps both ways, the motion keys and list, Reset, r) are
posted as key events the way Pilot posts them, and each is timed from posting
to the end of the first screen refresh after which nothing is left to paint:
bindings, the stepper, the screen's one settings watcher, the fit, readouts,
rebuilding every chart whose data changed, and Textual's frame pacing.
Pilot's `press` is not used for the timed keys because its idle detection
polls the event loop for tens of milliseconds after every key and competes
with the app, which would measure Pilot rather than the explorer.

Every round of keys starts at the defaults (it presses Reset), so the app's
caches of fits and figures are emptied before each round: a press is served
from a cache only when that round itself went there before (stepping back),
as in real use, never because an earlier round took the same path.

Goal: median <= 16.7 ms (one 60 Hz frame), p95 <= 33 ms.
"""

from __future__ import annotations

import asyncio
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from textual import events  # noqa: E402
from textual.screen import Screen  # noqa: E402

from tui.app import JointIdApp, MainScreen, cached_experiment  # noqa: E402
from tui.torque_plot import TorquePlot  # noqa: E402

PRESSES = 200
SIZE = (120, 40)
IDLE = 0.03
"""Pause before each key so presses do not overlap (a held key is coalesced anyway)."""
POLL = 0.0005
CLAMP_TIMEOUT = 0.25
"""A key that changes no setting (already at a range end) is counted, not timed."""

ROUND = [
    ("#noise", ["right"] * 4 + ["shift+right", "left", "shift+left"]),
    ("#samples", ["right"] * 3 + ["shift+right", "left", "shift+left"]),
    ("#seed", ["right"] * 3 + ["shift+right", "left"]),
    ("#motion", ["2", "3", "1", "down", "enter", "up", "enter"]),
    ("#noise", ["shift+right", "shift+right"]),
    ("#reset", ["enter"]),
    ("#motion", ["r"]),
]
"""(widget to focus, keys pressed there), repeated until 200 presses."""

stamps = {"watched": 0.0, "watches": 0, "chart_builds": 0}
slowest: list[tuple[float, str]] = []
"""(latency ms, control and key) of every timed press, to name the slow ones."""
frames: list[float] = []
"""End times of every screen refresh since the current key was posted."""


_refresh = Screen._compositor_refresh


def timed_refresh(self) -> None:
    _refresh(self)
    frames.append(time.perf_counter())


Screen._compositor_refresh = timed_refresh

_watch = MainScreen.watch_settings


def timed_watch(self, settings) -> None:
    _watch(self, settings)
    stamps["watched"] = time.perf_counter()
    stamps["watches"] += 1


MainScreen.watch_settings = timed_watch

_render = TorquePlot._render_figure


def counted_render(self, width, height):
    stamps["chart_builds"] += 1
    return _render(self, width, height)


TorquePlot._render_figure = counted_render


def percentile(values: list[float], fraction: float) -> float:
    """Nearest-rank percentile."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(fraction * (len(ordered) - 1)))]


def settled(screen) -> bool:
    """True when the screen has nothing left to lay out or paint."""
    return not (screen._layout_required or screen._dirty_widgets or screen._repaint_required)


def forget_everything(screen) -> None:
    """Empty the fit cache and every plot's figure cache (the next round starts cold)."""
    cached_experiment.cache_clear()
    for plot in screen.query(TorquePlot):
        plot._cache.clear()


async def measure() -> tuple[list[float], int, int, int]:
    app = JointIdApp()
    latencies: list[float] = []
    changed = unchanged = 0
    async with app.run_test(size=SIZE) as pilot:
        await pilot.pause()
        screen = app.screen
        stamps["chart_builds"] = 0
        while len(latencies) + unchanged < PRESSES:
            forget_everything(screen)
            for selector, keys in ROUND:
                screen.query_one(selector).focus()
                await pilot.pause()
                for key in keys:
                    if len(latencies) + unchanged >= PRESSES:
                        break
                    await asyncio.sleep(IDLE)  # untimed: the app is idle before each key
                    frames.clear()
                    watches = stamps["watches"]
                    start = time.perf_counter()
                    app.post_message(events.Key(key, key if len(key) == 1 else None))
                    # Poll lightly; Pilot's own idle wait would compete with the app here.
                    deadline = start + CLAMP_TIMEOUT
                    while stamps["watches"] == watches and time.perf_counter() < deadline:
                        await asyncio.sleep(POLL)
                    if stamps["watches"] == watches:  # clamped at a range end: nothing to show
                        unchanged += 1
                        continue
                    while not (settled(screen) and any(t >= stamps["watched"] for t in frames)):
                        await asyncio.sleep(POLL)
                    changed += 1
                    done = min(t for t in frames if t >= stamps["watched"])
                    latencies.append((done - start) * 1000)
                    slowest.append(((done - start) * 1000, f"{selector} {key}"))
    return latencies, changed, stamps["chart_builds"], unchanged


def main() -> None:
    latencies, changed, builds, unchanged = asyncio.run(measure())
    print(f"{len(latencies) + unchanged} presses at {SIZE[0]}x{SIZE[1]}: {changed} changed the "
          f"settings and were timed ({builds} charts built, the rest from cache); "
          f"{unchanged} hit a range end")
    print(f"key -> updated screen: median {statistics.median(latencies):.1f} ms, "
          f"p95 {percentile(latencies, 0.95):.1f} ms, max {max(latencies):.1f} ms")
    worst = ", ".join(f"{where} {ms:.0f} ms" for ms, where in sorted(slowest, reverse=True)[:5])
    print(f"slowest: {worst}")
    print("goal: median <= 16.7 ms, p95 <= 33 ms")


if __name__ == "__main__":
    main()
