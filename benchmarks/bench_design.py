"""Excitation design: one 3-harmonic, 8-start plain-model design against a 10,000-seed sweep, and key latency.

Run: PYTHONPATH=. .venv/bin/python benchmarks/bench_design.py [--rounds N] [--no-keys | --keys-only]

1. In-process, interleaved (the order alternates each round): `design_motion` with
   the defaults (plain model, rich motion's envelope, 3 harmonics, 8 starts, seed 0,
   24 samples, noise 0.20) against `run_sweep` of the same experiment on rich motion
   for 10,000 seeds, the work of `jointid sweep --noise 0.2 --seeds 10000`. Both
   warmed up first (imports, scipy.optimize). Prints min/median/max of each and
   the ratio of the medians. Goal: design <= 20x the sweep; the design's
   absolute seconds are context only (goal <= 10 s on this 2-core machine).
2. The same two as a user runs them, `python -m jointid design` and
   `python -m jointid sweep --noise 0.2 --seeds 10000`, in fresh processes
   (start-up and imports included), interleaved; prints the ratio of medians.
3. The explorer's key latency in the design view, headless at 120x40: Right and
   Left on the |q| max field, each timed from posting the key to the end of the
   first frame after the field's commit that leaves nothing to paint (the way
   bench_tui_keys.py times keys, with its helpers), idle against while a design
   of 1000 starts runs in the view's design process (its first start reported
   before the block's first key). At least 7 rounds, each an idle and a busy
   block of 25 keys, in alternating order (A B B A ...). Prints the median and
   p95 of each, busy / idle of the medians and of the p95s per round
   (min/median/max) and over all keys. Goal: both <= 1.5x.

Run `--keys-only` for part 3 alone (about 30 s).
"""

from __future__ import annotations

import argparse
import asyncio
import statistics
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from jointid.studies.design import DesignSpec, design_motion  # noqa: E402
from jointid.studies.sweep import run_sweep  # noqa: E402
from jointid.synthetic.settings import Settings  # noqa: E402

SEEDS = 10_000
SWEEP_SETTINGS = Settings(noise=0.2)
RATIO_GOAL = 20.0
SECONDS_GOAL = 10.0
LATENCY_GOAL = 1.5
LONG_STARTS = 1000
"""Starts of part 3's design: minutes of work, so it runs through every busy block."""
KEY_PRESSES = 25
"""Keys per block in part 3."""


def timed(function) -> float:
    start = time.perf_counter()
    function()
    return time.perf_counter() - start


def summary(values: list[float], scale: float = 1.0, unit: str = "s") -> str:
    values = [v * scale for v in values]
    return (f"min {min(values):8.3f} {unit}  median {statistics.median(values):8.3f} {unit}  "
            f"max {max(values):8.3f} {unit}")


def in_process(rounds: int) -> None:
    design_motion(DesignSpec())  # warm-up: scipy.optimize's import, caches
    run_sweep(SWEEP_SETTINGS, SEEDS)
    designs, sweeps = [], []
    for index in range(rounds):
        pair = [("design", lambda: design_motion(DesignSpec())), ("sweep", lambda: run_sweep(SWEEP_SETTINGS, SEEDS))]
        for name, work in (pair if index % 2 == 0 else pair[::-1]):
            (designs if name == "design" else sweeps).append(timed(work))
    ratio = statistics.median(designs) / statistics.median(sweeps)
    print(f"1. in process, {rounds} rounds interleaved")
    print(f"   design (plain, 3 harmonics, 8 starts): {summary(designs)}")
    print(f"   sweep (rich, noise 0.2, 10,000 seeds): {summary(sweeps)}")
    print(f"   design / sweep (medians): {ratio:.1f}x  (goal <= {RATIO_GOAL:g}x: "
          f"{'met' if ratio <= RATIO_GOAL else 'NOT met'}); design median {statistics.median(designs):.3f} s "
          f"(context, goal <= {SECONDS_GOAL:g} s)")


def command_line(rounds: int) -> None:
    commands = {"design": ["design"], "sweep": ["sweep", "--noise", "0.2", "--seeds", str(SEEDS)]}
    times = {name: [] for name in commands}
    root = Path(__file__).resolve().parent.parent
    for index in range(rounds):
        order = list(commands) if index % 2 == 0 else list(commands)[::-1]
        for name in order:
            times[name].append(timed(lambda: subprocess.run([sys.executable, "-m", "jointid", *commands[name]],
                                                              cwd=root, check=True, capture_output=True)))
    ratio = statistics.median(times["design"]) / statistics.median(times["sweep"])
    print(f"2. command line, fresh processes, {rounds} rounds interleaved")
    print(f"   jointid design:                        {summary(times['design'])}")
    print(f"   jointid sweep --noise 0.2 --seeds 10000: {summary(times['sweep'])}")
    print(f"   design / sweep (medians): {ratio:.1f}x")


async def key_latency(rounds: int, presses: int) -> list[tuple[list[float], list[float]]]:
    """(idle, busy) latencies of each round, in seconds: key press to fully updated design view."""
    # bench_tui_keys' way of timing a key to a settled screen: `press["watched"]` is set from inside the app
    # when the key took effect, and its `after_refresh` sets `press["updated"]` at the first frame after that
    # which leaves nothing to paint. It runs after each whole frame here, not after each compositor refresh
    # as there: the running design's progress readout lays the screen out most frames, and a frame that lays
    # out reads as unsettled from inside its compositor refresh (third_party.after_screen_update).
    from bench_tui_keys import IDLE, SETTLE_TIMEOUT, after_refresh, press
    from textual import events
    from textual.widgets import ProgressBar

    from tui.third_party import adapter as third_party
    from tui.app import JointIdApp
    from tui.screens.design import DesignScreen

    third_party.activate()  # as the app does when it starts
    undo_refresh_hook = third_party.after_screen_update(after_refresh)
    original_spec, original_commit = DesignScreen.spec, DesignScreen.commit_limit
    DesignScreen.spec = lambda self: replace(original_spec(self), starts=LONG_STARTS)  # outlasts a block

    def commit(self, field, value):
        original_commit(self, field, value)
        press["watched"].set()  # the key reached the view; the frame that shows it ends the timing

    DesignScreen.commit_limit = commit
    results = []
    app = JointIdApp(Settings(noise=0.2))
    try:
        async with app.run_test(size=(120, 40)) as pilot:
            await pilot.pause()
            await pilot.press("d")
            await pilot.pause()
            screen = app.screen
            screen.query_one("#q_max").focus()
            await pilot.pause()
            progress = screen.query_one(ProgressBar)
            for index in range(rounds):
                latencies = {False: [], True: []}
                for running in ((False, True) if index % 2 == 0 else (True, False)):  # A B B A ...
                    if running:
                        screen.action_run()
                        while not progress.progress:  # untimed: until the optimiser reports its first start
                            await asyncio.sleep(0.05)
                    for number in range(presses):
                        await asyncio.sleep(IDLE)  # untimed: the app is idle before each key
                        press.update(watched=asyncio.Event(), updated=asyncio.Event())
                        start = time.perf_counter()
                        app.post_message(events.Key("right" if number % 2 == 0 else "left", None))
                        await asyncio.wait_for(press["updated"].wait(), SETTLE_TIMEOUT)
                        latencies[running].append(press["done_at"] - start)
                    if running:
                        if not screen.running:
                            raise RuntimeError("the design finished during the block: make it longer")
                        screen.action_cancel()
                        while screen.running:
                            await asyncio.sleep(0.01)
                        progress.update(progress=0)
                results.append((latencies[False], latencies[True]))
            await pilot.press("escape")
    finally:
        press.update(watched=None, updated=None)
        undo_refresh_hook()
        DesignScreen.spec, DesignScreen.commit_limit = original_spec, original_commit
    return results


def keys(rounds: int, presses: int) -> None:
    from bench_tui_keys import percentile

    results = asyncio.run(key_latency(rounds, presses))
    idle = [value for one, _ in results for value in one]
    busy = [value for _, one in results for value in one]
    per_round = {name: [f(b) / f(i) for i, b in results] for name, f in
                 (("median", statistics.median), ("p95", lambda v: percentile(v, 0.95)))}
    print(f"3. design view, key press to fully updated screen, {rounds} rounds of an idle and a busy block "
          f"(alternating) of {presses} keys; busy: a {LONG_STARTS}-start design running")
    for name, values in (("idle:          ", idle), ("design running:", busy)):
        print(f"   {name}  median {1000 * statistics.median(values):6.2f} ms  "
              f"p95 {1000 * percentile(values, 0.95):6.2f} ms")
    for name, ratios in per_round.items():
        print(f"   busy / idle {name:6} per round: min {min(ratios):.2f}x  median {statistics.median(ratios):.2f}x  "
              f"max {max(ratios):.2f}x")
    pooled = {"median": statistics.median(busy) / statistics.median(idle),
              "p95": percentile(busy, 0.95) / percentile(idle, 0.95)}
    verdict = "met" if max(pooled.values()) <= LATENCY_GOAL else "NOT met"
    print(f"   busy / idle, all keys: median {pooled['median']:.2f}x, p95 {pooled['p95']:.2f}x  "
          f"(goal both <= {LATENCY_GOAL:g}x: {verdict})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--no-keys", action="store_true", help="skip part 3")
    parser.add_argument("--keys-only", action="store_true", help="run part 3 only")
    args = parser.parse_args()
    if not args.keys_only:
        in_process(args.rounds)
        command_line(max(3, args.rounds // 2))
    if not args.no_keys:
        keys(rounds=max(7, args.rounds), presses=KEY_PRESSES)


if __name__ == "__main__":
    main()
