"""Key press to fully updated explorer screen, headless at 120x40, over 200 presses.

Run: .venv/bin/python benchmarks/bench_tui_keys.py

The app runs headless under Pilot (`run_test`), which also focuses each control
in turn. The 200 presses across every control (noise, samples and seed fields
with small and big steps both ways, the motion keys and list, Reset, r) are
posted as key events the way Pilot posts them, and each is timed from posting
to the end of the first screen refresh, after the screen's settings watcher ran,
that leaves nothing to paint: bindings, the stepper, the watcher, the fit,
readouts, rebuilding every chart whose data changed, and Textual's frame pacing.
The benchmark waits on events set from inside the app; Pilot's `press` is not
used for the timed keys because its idle detection polls the event loop for tens
of milliseconds after every key and competes with the app, which would measure
Pilot rather than the explorer (a polling loop of its own did the same, a little).

The 200 presses run three times, each in a fresh app, because this shared
machine's speed drifts between runs; each run and all 600 presses are reported,
with one chart built by plotext alone timed before and after as a gauge of the
machine's speed at the time (the same code's median went from 12.6 to 20 ms as it
slowed).

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

from tui.app import JointIdApp  # noqa: E402
from tui.main_screen import MainScreen, cached_experiment  # noqa: E402
from tui.torque_plot import TorquePlot  # noqa: E402

PRESSES = 200
RUNS = 3
SIZE = (120, 40)
IDLE = 0.03
"""Pause before each key so presses do not overlap (a held key is coalesced anyway)."""
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
press = {"watched": None, "updated": None, "done_at": 0.0}
"""The timed press's events: its settings watcher ran; a frame left the screen fully updated."""


_refresh = Screen._compositor_refresh


def timed_refresh(self) -> None:
    _refresh(self)
    # The press is done at the first frame after its watcher that leaves nothing to paint.
    watched, updated = press["watched"], press["updated"]
    if watched is not None and watched.is_set() and updated is not None and not updated.is_set() \
            and settled(self):
        press["done_at"] = time.perf_counter()
        updated.set()


Screen._compositor_refresh = timed_refresh

_watch = MainScreen.watch_settings


def timed_watch(self, settings) -> None:
    _watch(self, settings)
    stamps["watched"] = time.perf_counter()
    stamps["watches"] += 1
    if press["watched"] is not None:
        press["watched"].set()


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
                    press.update(watched=asyncio.Event(), updated=asyncio.Event())
                    start = time.perf_counter()
                    app.post_message(events.Key(key, key if len(key) == 1 else None))
                    # Wait on events set from inside the app, not by polling: a polling loop
                    # (or Pilot's idle wait) would run in the app's event loop and slow it.
                    try:
                        await asyncio.wait_for(press["watched"].wait(), CLAMP_TIMEOUT)
                    except asyncio.TimeoutError:  # clamped at a range end: nothing to show
                        unchanged += 1
                        continue
                    await press["updated"].wait()
                    changed += 1
                    latency = (press["done_at"] - start) * 1000
                    latencies.append(latency)
                    slowest.append((latency, f"{selector} {key}"))
    return latencies, changed, stamps["chart_builds"], unchanged


def reference_workload_ms() -> float:
    """Median time to build one torque chart with plotext, outside the app: how fast this shared
    machine runs code like the explorer's (allocation-heavy Python) just now."""
    from plotext._figure import _figure_class

    from jointid.experiment import run_experiment
    from jointid.settings import DEFAULT_SETTINGS
    from jointid.present.charts import training_chart
    from tui.charts import draw_torque_chart
    from tui.torque_plot import build_matrix

    data, figure, times = training_chart(run_experiment(DEFAULT_SETTINGS)), _figure_class(), []
    for _ in range(60):
        start = time.perf_counter()
        draw_torque_chart(figure, data, (255, 0, 0), (0, 0, 255))
        build_matrix(figure, 74, 14)
        times.append((time.perf_counter() - start) * 1000)
    return statistics.median(times)


def main() -> None:
    print(f"machine speed: one chart built by plotext alone in {reference_workload_ms():.2f} ms "
          f"(longer when the shared machine is busy; key latencies scale with it)")
    everything: list[float] = []
    for run in range(1, RUNS + 1):
        slowest.clear()
        latencies, changed, builds, unchanged = asyncio.run(measure())
        everything += latencies
        print(f"run {run}: {len(latencies) + unchanged} presses at {SIZE[0]}x{SIZE[1]}, {changed} changed "
              f"the settings and were timed ({builds} charts built, the rest from cache), "
              f"{unchanged} hit a range end")
        print(f"  key -> updated screen: median {statistics.median(latencies):.1f} ms, "
              f"p95 {percentile(latencies, 0.95):.1f} ms, max {max(latencies):.1f} ms")
        worst = ", ".join(f"{where} {ms:.0f} ms" for ms, where in sorted(slowest, reverse=True)[:5])
        print(f"  slowest: {worst}")
    print(f"all {len(everything)} timed presses: median {statistics.median(everything):.1f} ms, "
          f"p95 {percentile(everything, 0.95):.1f} ms (goal: median <= 16.7 ms, p95 <= 33 ms)")
    print(f"machine speed after: one chart in {reference_workload_ms():.2f} ms")


if __name__ == "__main__":
    main()
