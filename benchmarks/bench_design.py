"""Excitation design: one 3-harmonic, 8-start plain-model design against a 10,000-seed sweep, and key latency.

Run: PYTHONPATH=. .venv/bin/python benchmarks/bench_design.py [--rounds N] [--no-keys]

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
3. The explorer's key latency in the design view, headless at 120x40: Right on
   the |q| max field, timed from posting the key to the field's commit callback
   (the key's whole handling on the app's loop), idle against while a design
   of 1000 starts runs in the view's worker thread. Blocks of presses alternate
   idle / busy. Prints median and p95 of each and busy / idle. Goal <= 1.5x.
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

from jointid.design import DesignSpec, design_motion  # noqa: E402
from jointid.settings import Settings  # noqa: E402
from jointid.sweep import run_sweep  # noqa: E402

SEEDS = 10_000
SWEEP_SETTINGS = Settings(noise=0.2)
RATIO_GOAL = 20.0
SECONDS_GOAL = 10.0
LATENCY_GOAL = 1.5


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


async def key_latency(blocks: int, presses: int) -> tuple[list[float], list[float]]:
    from textual import events

    from tui.app import JointIdApp
    from tui.screens.design import DesignScreen

    original_spec = DesignScreen.spec
    DesignScreen.spec = lambda self: replace(original_spec(self), starts=1000)  # a design that outlasts a block
    committed = asyncio.Event()
    original_commit = DesignScreen.commit_limit

    def commit(self, field, value):
        original_commit(self, field, value)
        committed.set()

    DesignScreen.commit_limit = commit
    idle, busy = [], []
    app = JointIdApp(Settings(noise=0.2))
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.pause()
        await pilot.press("d")
        await pilot.pause()
        screen = app.screen
        field = screen.query_one("#q_max")
        field.focus()
        await pilot.pause()
        for block in range(2 * blocks):
            running = block % 2 == 1
            if running:
                screen.action_run()
                await asyncio.sleep(0.3)  # into the optimiser's loop
            for press in range(presses):
                key = "right" if press % 2 == 0 else "left"
                committed.clear()
                start = time.perf_counter()
                app.post_message(events.Key(key, None))
                await asyncio.wait_for(committed.wait(), 10)
                (busy if running else idle).append(time.perf_counter() - start)
                await asyncio.sleep(0.02)
            if running:
                if not screen.running:
                    raise RuntimeError("the design finished during the block: make it longer")
                screen.action_cancel()
                while screen.running:  # the thread notices at its next criterion evaluation
                    await asyncio.sleep(0.01)
        await pilot.press("escape")
    DesignScreen.spec, DesignScreen.commit_limit = original_spec, original_commit
    return idle, busy


def keys(blocks: int, presses: int) -> None:
    idle, busy = asyncio.run(key_latency(blocks, presses))
    p95 = lambda values: sorted(values)[int(0.95 * (len(values) - 1))]  # noqa: E731
    ratio = statistics.median(busy) / statistics.median(idle)
    print(f"3. design view key latency (post to commit), {blocks} idle and {blocks} busy blocks of {presses} keys")
    print(f"   idle:            median {1000 * statistics.median(idle):6.2f} ms  p95 {1000 * p95(idle):6.2f} ms")
    print(f"   design running:  median {1000 * statistics.median(busy):6.2f} ms  p95 {1000 * p95(busy):6.2f} ms")
    print(f"   busy / idle (medians): {ratio:.2f}x, p95: {p95(busy) / p95(idle):.2f}x  "
          f"(goal <= {LATENCY_GOAL:g}x: {'met' if ratio <= LATENCY_GOAL else 'NOT met'})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--no-keys", action="store_true")
    args = parser.parse_args()
    in_process(args.rounds)
    command_line(max(3, args.rounds // 2))
    if not args.no_keys:
        keys(blocks=4, presses=25)


if __name__ == "__main__":
    main()
