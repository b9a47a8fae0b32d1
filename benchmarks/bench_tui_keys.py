"""Key press to fully updated explorer screen, headless at 120x40, over 200 presses.

Run: .venv/bin/python benchmarks/bench_tui_keys.py [--gc tuned|stock|both] [--runs N]

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

With `--gc both` the runs alternate (A B B A ...) between the app's garbage-collection tuning
(`JointIdApp.on_ready`) and Python's stock collector, and the ratios stock / tuned
of the min, median, p95 and max latency are printed: the figure that decides
whether the tuning stays. Each app restores the collector when it exits, so
the runs do not inherit each other's setting.

Goal: median <= 16.7 ms (one 60 Hz frame), p95 <= 33 ms.
"""

from __future__ import annotations

import argparse
import asyncio
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from textual import events  # noqa: E402

from jointid.settings import Settings  # noqa: E402
from tui import third_party  # noqa: E402
from tui.app import JointIdApp  # noqa: E402
from tui.screens.main import MainScreen, cached_experiment  # noqa: E402
from tui.widgets.torque_plot import TorquePlot  # noqa: E402

PRESSES = 200
RUNS = 3
SIZE = (120, 40)
IDLE = 0.03
"""Pause before each key so presses do not overlap (a held key is coalesced anyway)."""
CLAMP_TIMEOUT = 0.25
"""A key that changes no setting (already at a range end) is counted, not timed."""
SETTLE_TIMEOUT = 10.0
"""Seconds a press may take to leave the screen settled before the benchmark stops with an error."""

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


def after_refresh(screen) -> None:
    """Called after every screen refresh: the press is done at the first frame after its
    watcher that leaves nothing to paint."""
    watched, updated = press["watched"], press["updated"]
    if watched is not None and watched.is_set() and updated is not None and not updated.is_set() \
            and third_party.screen_settled(screen):
        press["done_at"] = time.perf_counter()
        updated.set()


_show = MainScreen.show_source


def timed_show(self) -> None:
    _show(self)
    stamps["watched"] = time.perf_counter()
    stamps["watches"] += 1
    if press["watched"] is not None:
        press["watched"].set()


MainScreen.show_source = timed_show

_render = TorquePlot._render_figure


def counted_render(self, width, height):
    stamps["chart_builds"] += 1
    return _render(self, width, height)


TorquePlot._render_figure = counted_render


def percentile(values: list[float], fraction: float) -> float:
    """Nearest-rank percentile."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(fraction * (len(ordered) - 1)))]


def forget_everything(screen) -> None:
    """Empty the fit cache and every plot's figure cache (the next round starts cold)."""
    cached_experiment.cache_clear()
    for plot in screen.query(TorquePlot):
        plot._cache.clear()


async def measure(tune_gc: bool = True, model: str = "plain") -> tuple[list[float], int, int, int]:
    app = JointIdApp(Settings(model=model))
    app.tune_gc = tune_gc
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
                    try:  # a frame that never settles would be a bug: say so instead of waiting forever
                        await asyncio.wait_for(press["updated"].wait(), SETTLE_TIMEOUT)
                    except asyncio.TimeoutError:
                        raise SystemExit(f"{selector} {key}: the screen never settled after the push-down")
                    changed += 1
                    latency = (press["done_at"] - start) * 1000
                    latencies.append(latency)
                    slowest.append((latency, f"{selector} {key}"))
    return latencies, changed, stamps["chart_builds"], unchanged


def reference_workload_ms() -> float:
    """Median time to build one torque chart with plotext, outside the app: how fast this shared
    machine runs code like the explorer's (allocation-heavy Python) just now."""
    from jointid.experiment import run_experiment
    from jointid.settings import DEFAULT_SETTINGS
    from jointid.present.charts import training_chart
    from tui.widgets.charts import draw_torque_chart

    data, figure, times = training_chart(run_experiment(DEFAULT_SETTINGS)), third_party.new_figure(), []
    for _ in range(60):
        start = time.perf_counter()
        draw_torque_chart(figure, data, (255, 0, 0), (0, 0, 255))
        third_party.build_matrix(figure, 74, 14)
        times.append((time.perf_counter() - start) * 1000)
    return statistics.median(times)


def summary(latencies: list[float]) -> str:
    """min, median, p95 and max of some latencies, in ms, and how many took over two frames."""
    return (f"min {min(latencies):.1f}, median {statistics.median(latencies):.1f}, "
            f"p95 {percentile(latencies, 0.95):.1f}, max {max(latencies):.1f} ms; "
            f"{sum(ms > 33.3 for ms in latencies)} over 33.3 ms")


def compare_models_latency(model: str, rounds: int) -> None:
    """Key latency with `model` against the plain model, alternating fresh apps (A B B A ...)."""
    third_party.activate()
    third_party.after_compositor_refresh(after_refresh)
    everything: dict[str, list[float]] = {"plain": [], model: []}
    order = [name for pair in range(rounds) for name in (("plain", model) if pair % 2 == 0 else (model, "plain"))]
    for name in order:
        latencies, _, _, _ = asyncio.run(measure(model=name))
        everything[name] += latencies
        print(f"{name}: {summary(latencies)}")
    plain, other = everything["plain"], everything[model]
    print(f"{model} / plain, all presses: median {statistics.median(other) / statistics.median(plain):.2f}, "
          f"p95 {percentile(other, 0.95) / percentile(plain, 0.95):.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--gc", choices=("tuned", "stock", "both"), default="tuned",
                        help="the app's garbage-collection tuning (JointIdApp.on_ready) on, off, or "
                             "alternating run by run (default: tuned, as the app ships)")
    parser.add_argument("--runs", type=int, default=RUNS, help=f"fresh apps per mode (default {RUNS})")
    parser.add_argument("--model", default=None, metavar="NAME",
                        help="also time the explorer fitting this model, alternating with the plain model, "
                             "and print the ratio (e.g. coulomb+bias)")
    args = parser.parse_args()
    if args.model is not None:
        compare_models_latency(args.model, args.runs)
        return
    modes = ["tuned", "stock"] if args.gc == "both" else [args.gc]

    for line in third_party.activate():  # as the app does when it starts; the gauge below needs it too
        print(f"adapter: {line}")
    third_party.after_compositor_refresh(after_refresh)
    print(f"machine speed: one chart built by plotext alone in {reference_workload_ms():.2f} ms "
          f"(longer when the shared machine is busy; key latencies scale with it)")
    everything: dict[str, list[float]] = {mode: [] for mode in modes}
    runs: dict[str, list[list[float]]] = {mode: [] for mode in modes}
    # Alternate, in the order A B B A A B ..., so both modes see the same drift and go first equally.
    order = [mode for pair in range(args.runs) for mode in (modes if pair % 2 == 0 else modes[::-1])]
    for run, mode in enumerate(order, 1):
        slowest.clear()
        latencies, changed, builds, unchanged = asyncio.run(measure(tune_gc=mode == "tuned"))
        everything[mode] += latencies
        runs[mode].append(latencies)
        print(f"run {run} (gc {mode}): {len(latencies) + unchanged} presses at {SIZE[0]}x{SIZE[1]}, "
              f"{changed} changed the settings and were timed ({builds} charts built, the rest from "
              f"cache), {unchanged} hit a range end")
        print(f"  key -> updated screen: {summary(latencies)}")
        worst = ", ".join(f"{where} {ms:.0f} ms" for ms, where in sorted(slowest, reverse=True)[:5])
        print(f"  slowest: {worst}")
    for mode, latencies in everything.items():
        print(f"gc {mode}: all {len(latencies)} timed presses: {summary(latencies)} "
              f"(goal: median <= 16.7 ms, p95 <= 33 ms)")
    if len(modes) == 2:
        measures = (("min", min), ("median", statistics.median), ("p95", lambda v: percentile(v, 0.95)),
                    ("max", max))
        tuned, stock = everything["tuned"], everything["stock"]
        print("stock / tuned, all presses: " + ", ".join(
            f"{name} {f(stock) / f(tuned):.2f}" for name, f in measures))
        # A run the shared machine slowed down moves the pooled figures; the median run's do not.
        typical = {mode: {name: statistics.median(f(one) for one in runs[mode]) for name, f in measures}
                   for mode in modes}
        print("median run: " + "; ".join(
            f"{mode} " + ", ".join(f"{name} {value:.1f}" for name, value in typical[mode].items()) + " ms"
            for mode in modes))
        print("stock / tuned, median run: " + ", ".join(
            f"{name} {typical['stock'][name] / typical['tuned'][name]:.2f}" for name, _ in measures))
    print(f"machine speed after: one chart in {reference_workload_ms():.2f} ms")


if __name__ == "__main__":
    main()
