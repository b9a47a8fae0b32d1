"""Key press to fully updated explorer screen, headless at 120x40, against a stock PlotextPlot.

Run: .venv/bin/python benchmarks/bench_tui_keys.py [--runs N] [--gc tuned|stock|both] [--model NAME] [--adapter KEY]

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

The baseline is what a user of textual-plotext would write for one chart: a
Textual app holding one stock `PlotextPlot` the size of the explorer's training
chart, which on every key press redraws the training chart of the settings the
explorer reached with that press (the same data, stock plotext calls, plotext's
own functions: the explorer's plotext adapters are switched off for it), timed
the same way, from posting the key to the first frame that leaves nothing to
paint. Both apps run under the same garbage-collection tuning (the explorer's
`JointIdApp.on_ready`: this process also holds the explorer's heap, whose
full collections would otherwise slow only the baseline), and both are warmed
up by one whole untimed round. The explorer does more per press (a fit,
readouts, two charts). Rounds
alternate the two (A B B A ...), each in a fresh app; each round prints the
ratios explorer / stock of the median and the p95 latency of its presses, and
the summary gives their min / median / max over the rounds. Goal: both
medians <= 1.0. Milliseconds are printed for scale only: this shared machine's
speed drifts by a factor of 2 to 8 between hours.

Every round of keys starts at the defaults (it presses Reset), so the app's
caches of fits and figures are emptied before each round: a press is served
from a cache only when that round itself went there before (stepping back),
as in real use, never because an earlier round took the same path.

With `--gc both` the explorer's runs alternate instead between the app's garbage-collection tuning
(`JointIdApp.on_ready`) and Python's stock collector, and the ratios stock / tuned
of the min, median, p95 and max latency are printed: the figure that decides
whether the tuning stays. Each app restores the collector when it exits, so
the runs do not inherit each other's setting.

With `--adapter KEY` (a key of `tui.third_party.adapter.ADAPTERS`, e.g. chart-matrix) the
explorer's runs alternate between every adapter on and that one off (its stock path), and
the same ratios, stock / adapter, are printed: what the adapter buys a key press is one
minus the inverse of the median's (benchmarks/bench_startup_budget.py times the start-up).
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

from jointid.synthetic.settings import Settings  # noqa: E402
from tui.third_party import adapter as third_party  # noqa: E402
from tui.app import JointIdApp  # noqa: E402
from tui.screens.main import MainScreen, cached_experiment  # noqa: E402
from tui.widgets.torque_plot import TorquePlot  # noqa: E402

PRESSES = 200
RUNS = 3
ROUNDS = 7
"""Rounds of explorer and stock chart, for the ratio (at least 7, interleaved)."""
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
reached: list = []
"""The explorer's settings after each press that changed them, in order (the stock chart redraws their data)."""
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
    if press["watched"] is not None and not press["watched"].is_set():
        # Only a timed press's settings: the mount's first show is no press, and counting it
        # shifted the stock chart's data one press behind the explorer's.
        reached.append(self.settings)
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
    from jointid.present.charts import training_chart
    from jointid.studies.experiment import run_experiment
    from jointid.synthetic.settings import DEFAULT_SETTINGS
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


class StockChart:
    """The baseline: a Textual app with one stock PlotextPlot that redraws a given chart on every key."""

    @staticmethod
    def app(datasets: list, size: tuple[int, int]):
        """A fresh app redrawing datasets[k] (ChartData) at the k-th key, its plot `size` (columns, rows)."""
        from textual.app import App, ComposeResult
        from textual_plotext import PlotextPlot

        class Stock(App):
            CSS = f"PlotextPlot {{ width: {size[0]}; height: {size[1]}; }}"
            # The explorer's garbage-collection tuning (JointIdApp.on_ready), so both apps run
            # under the same collector: this process holds the explorer's heap too, and stock
            # full collections walking it would slow the baseline, not anything it draws.
            tune_gc = restore_gc = True
            on_ready = JointIdApp.on_ready
            on_unmount = JointIdApp.on_unmount
            resume_gc = JointIdApp.resume_gc  # called by both (the app pauses the collector until its first frame)

            def compose(self) -> ComposeResult:
                yield PlotextPlot()

            def on_mount(self) -> None:
                self.next_chart = 0

            def on_key(self, event: events.Key) -> None:
                data = datasets[self.next_chart % len(datasets)]
                self.next_chart += 1
                plot = self.query_one(PlotextPlot)
                plt = plot.plt
                plt.clear_data()
                plt.title(data.titles[0])
                plt.xlabel(data.x_label)
                plt.ylabel("Torque (N m)")
                if data.line is not None:
                    plt.plot(data.t, data.line, label=data.line_label)
                plt.scatter(data.t, data.dots, label=data.dots_label)
                plot.refresh()
                if press["watched"] is not None:
                    press["watched"].set()

        return Stock()


async def measure_stock(datasets: list, size: tuple[int, int], presses: int) -> list[float]:
    """Latencies (ms) of `presses` keys, each redrawing the next dataset in a stock PlotextPlot."""
    app = StockChart.app(datasets, size)
    latencies: list[float] = []
    async with app.run_test(size=SIZE) as pilot:
        await pilot.pause()
        while len(latencies) < presses:
            await asyncio.sleep(IDLE)
            press.update(watched=asyncio.Event(), updated=asyncio.Event())
            start = time.perf_counter()
            app.post_message(events.Key("x", "x"))
            await asyncio.wait_for(press["watched"].wait(), SETTLE_TIMEOUT)
            await asyncio.wait_for(press["updated"].wait(), SETTLE_TIMEOUT)
            latencies.append((press["done_at"] - start) * 1000)
    return latencies


def training_chart_size() -> tuple[int, int]:
    """The explorer's training plot's size (columns, rows) at SIZE."""

    async def size() -> tuple[int, int]:
        app = JointIdApp(Settings())
        async with app.run_test(size=SIZE) as pilot:
            await pilot.pause()
            plot = app.screen.query_one("#training-chart").query_one(TorquePlot)
            return plot.content_region.width, plot.content_region.height

    return asyncio.run(size())


def compare_with_stock_chart(rounds: int) -> bool:
    """Explorer against the stock one-chart app, alternating fresh apps (A B B A ...); print the ratios.

    Returns whether both goals are met.
    """
    from jointid.present.charts import training_chart
    from jointid.studies.experiment import run_experiment

    third_party.after_compositor_refresh(after_refresh)
    size = training_chart_size()
    reached.clear()
    asyncio.run(measure())  # warm-up, and the settings sequence every round walks again
    datasets = [training_chart(run_experiment(settings)) for settings in reached]
    # The stock app's warm-up too, a whole round like the explorer's: its first run would
    # otherwise pay textual-plotext's imports and start with cold caches.
    third_party.uninstall()
    asyncio.run(measure_stock(datasets, size, len(datasets)))
    print(f"{len(datasets)} timed presses per round at {SIZE[0]}x{SIZE[1]}; the stock PlotextPlot is "
          f"{size[0]}x{size[1]}, the explorer's training chart; {rounds} rounds")
    ratios: dict[str, list[float]] = {"median": [], "p95": []}
    pooled: dict[str, list[float]] = {"explorer": [], "stock": []}
    for index in range(rounds):
        order = ("explorer", "stock") if index % 2 == 0 else ("stock", "explorer")
        latencies = {}
        for name in order:
            if name == "explorer":
                third_party.activate()  # the explorer as it ships
                latencies[name], _, _, _ = asyncio.run(measure())
            else:
                third_party.uninstall()  # plotext's own functions for the stock widget
                latencies[name] = asyncio.run(measure_stock(datasets, size, len(datasets)))
            pooled[name] += latencies[name]
        explorer, stock = latencies["explorer"], latencies["stock"]
        ratios["median"].append(statistics.median(explorer) / statistics.median(stock))
        ratios["p95"].append(percentile(explorer, 0.95) / percentile(stock, 0.95))
        print(f"round {index + 1}: explorer / stock, median {ratios['median'][-1]:.2f}, p95 {ratios['p95'][-1]:.2f} "
              f"(for scale: explorer median {statistics.median(explorer):.1f} ms, stock "
              f"{statistics.median(stock):.1f} ms)")
    third_party.activate()
    print()
    print("explorer / stock PlotextPlot over the rounds, min / median / max:")
    met = True
    for name, values in ratios.items():
        middle = statistics.median(values)
        met = met and middle <= 1.0
        print(f"  {name:<7}{min(values):.2f} / {middle:.2f} / {max(values):.2f}  "
              f"goal <= 1.0: {'met' if middle <= 1.0 else 'MISSED'}")
    explorer, stock = pooled["explorer"], pooled["stock"]
    print(f"all presses pooled: median {statistics.median(explorer) / statistics.median(stock):.2f}, "
          f"p95 {percentile(explorer, 0.95) / percentile(stock, 0.95):.2f}")
    return met


def without_adapter(key: str):
    """Turn every adapter on but `key` (its stock path); returns the undo, which turns them all on."""
    check = third_party.check

    def check_without():
        usable, lines = check()
        return usable | {key: False}, lines

    third_party.uninstall()
    third_party.check = check_without
    third_party.activate()

    def undo() -> None:
        third_party.uninstall()
        third_party.check = check
        third_party.activate()

    return undo


def compare_adapter_latency(key: str, runs: int) -> None:
    """Key latency with every adapter against `key` switched off, alternating fresh apps (A B B A ...)."""
    third_party.activate()
    third_party.after_compositor_refresh(after_refresh)
    asyncio.run(measure())  # warm-up, untimed: imports and first-use caches
    everything: dict[str, list[float]] = {"adapter": [], "stock": []}
    medians: dict[str, list[float]] = {"adapter": [], "stock": []}
    order = [name for pair in range(runs) for name in (("adapter", "stock") if pair % 2 == 0 else ("stock", "adapter"))]
    for name in order:
        undo = without_adapter(key) if name == "stock" else None
        try:
            latencies, _, _, _ = asyncio.run(measure())
        finally:
            if undo is not None:
                undo()
        everything[name] += latencies
        medians[name].append(statistics.median(latencies))
        print(f"{key} {'off' if name == 'stock' else 'on'}: {summary(latencies)}")
    adapter, stock = everything["adapter"], everything["stock"]
    ratios = [s / a for s, a in zip(medians["stock"], medians["adapter"])]
    print(f"stock / adapter ({key}), all presses: median {statistics.median(stock) / statistics.median(adapter):.3f}, "
          f"p95 {percentile(stock, 0.95) / percentile(adapter, 0.95):.3f}; per pair of runs, medians: "
          f"{min(ratios):.3f} / {statistics.median(ratios):.3f} / {max(ratios):.3f}")
    print(f"what it buys a key press (1 - adapter / stock, medians per pair): "
          f"{min(1 - 1 / r for r in ratios):+.3f} / {statistics.median(1 - 1 / r for r in ratios):+.3f} / "
          f"{max(1 - 1 / r for r in ratios):+.3f}")


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
    parser.add_argument("--gc", choices=("tuned", "stock", "both"), default=None,
                        help="instead of the stock chart, time the app's garbage-collection tuning "
                             "(JointIdApp.on_ready) on, off, or alternating run by run")
    parser.add_argument("--runs", type=int, default=None,
                        help=f"rounds against the stock chart (default {ROUNDS}), or fresh apps per mode with "
                             f"--gc or --model (default {RUNS})")
    parser.add_argument("--model", default=None, metavar="NAME",
                        help="also time the explorer fitting this model, alternating with the plain model, "
                             "and print the ratio (e.g. coulomb+bias)")
    parser.add_argument("--adapter", default=None, metavar="KEY",
                        choices=[adapter.key for adapter in third_party.ADAPTERS],
                        help="time the explorer with every adapter on against this one off, alternating")
    args = parser.parse_args()
    if args.adapter is not None:
        compare_adapter_latency(args.adapter, args.runs or RUNS)
        return
    if args.model is not None:
        compare_models_latency(args.model, args.runs or RUNS)
        return
    if args.gc is None:
        raise SystemExit(0 if compare_with_stock_chart(args.runs or ROUNDS) else 1)
    args.runs = args.runs or RUNS
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
        print(f"gc {mode}: all {len(latencies)} timed presses: {summary(latencies)}")
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
