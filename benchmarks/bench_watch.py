"""Live identification's cost against the time watched: a Watcher fed a simulated 1 kHz arm for one minute beside
one fed MINUTES minutes (default 60: an hour at 1 kHz), both in 20 ms blocks (a NetworkTables poll's worth) with a
refresh a second while fed.

Then ROUNDS rounds, interleaved so that the machine's drift falls on both alike: each round gives each watcher its
next 20 ms block (timing `add`) and a refresh (timing `refresh`), the long watcher's time divided by the short
one's. Printed: min / median / max of those ratios (flat, a cost that does not grow with the time watched, is
1.0), the ratio of the numbers each holds (`Watcher.state_size`) and of the bytes tracemalloc counts as allocated
while each was fed. Beside them the baseline a user would write instead, numpy.linalg.lstsq over every decimated
row so far, timed alike on a minute's rows and on MINUTES minutes': its ratio grows with the minutes.

    PYTHONPATH=. .venv/bin/python benchmarks/bench_watch.py [MINUTES [ROUNDS]]     (defaults 60 and 300)
"""

from __future__ import annotations

import statistics
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from jointid.live.received import Received  # noqa: E402
from jointid.studies.watch import Watcher  # noqa: E402

RATE = 1000.0
BLOCK = 20
"""Samples per block: 20 ms at 1 kHz."""
G = 9.81


def arm(first: float, seconds: float, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """A simulated arm (sum of sines, Coulomb friction, bias, Gaussian torque noise) at 1 kHz from `first` s."""
    t = first + np.arange(int(round(seconds * RATE))) / RATE
    motion = [(0.8, 0.3, 0.0), (0.4, 0.7, 1.0), (0.2, 1.3, 2.0)]
    q = sum(a * np.sin(2 * np.pi * f * t + p) for a, f, p in motion)
    qd = sum(a * 2 * np.pi * f * np.cos(2 * np.pi * f * t + p) for a, f, p in motion)
    qdd = sum(-a * (2 * np.pi * f) ** 2 * np.sin(2 * np.pi * f * t + p) for a, f, p in motion)
    tau = 0.05 * qdd + 0.3 * G * np.cos(q) + 0.1 * qd + 0.2 * np.sign(qd) + 0.2 + 0.5 * rng.standard_normal(len(t))
    return {"t": t, "q": q, "tau": tau, "qd": qd, "qdd": qdd}


def blocks(samples: dict[str, np.ndarray]):
    """The samples as Received blocks of BLOCK samples (t, q and tau, as a source gives them)."""
    for first in range(0, len(samples["t"]), BLOCK):
        yield Received({name: samples[name][first:first + BLOCK] for name in ("t", "q", "tau")})


def fed(minutes: int, rng: np.random.Generator) -> tuple[Watcher, int, list[np.ndarray]]:
    """A watcher fed `minutes` minutes (a refresh a second), the bytes allocated meanwhile that stayed allocated,
    and the baseline's rows: every decimated row as a user would keep them."""
    watcher = Watcher()
    rows = []
    tracemalloc.start()
    for minute in range(minutes):
        samples = arm(60.0 * minute, 60.0, rng)
        for k, block in enumerate(blocks(samples)):
            watcher.add(block)
            if (k + 1) % int(RATE / BLOCK) == 0:
                watcher.refresh()
        step = watcher.filter.decimation
        s = {name: values[::step] for name, values in samples.items()}
        rows.append(np.column_stack([s["qdd"], G * np.cos(s["q"]), s["qd"], np.sign(s["qd"]), np.ones_like(s["q"]),
                                     s["tau"]]))
        del samples, s
    held, _ = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    rows_bytes = sum(r.nbytes for r in rows)
    return watcher, held - rows_bytes, rows


def spread(values: list[float]) -> str:
    """min / median / max."""
    values = sorted(values)
    return f"{values[0]:.2f} / {statistics.median(values):.2f} / {values[-1]:.2f}"


def main(minutes: int, rounds: int) -> None:
    """Feed both watchers, then time them interleaved and print the ratios."""
    fed(1, np.random.default_rng(2))  # every module a watcher loads, loaded before any allocation is counted
    short, short_bytes, short_rows = fed(1, np.random.default_rng(3))
    long, long_bytes, long_rows = fed(minutes, np.random.default_rng(3))
    rng = np.random.default_rng(4)
    extra = {"short": blocks(arm(60.0, rounds * BLOCK / RATE, rng)),
             "long": blocks(arm(60.0 * minutes, rounds * BLOCK / RATE, rng))}
    watchers = {"short": short, "long": long}
    adds, refreshes, baseline = [], [], []
    short_matrix, long_matrix = np.vstack(short_rows), np.vstack(long_rows)
    for round_ in range(rounds):
        times = {}
        order = ("short", "long") if round_ % 2 == 0 else ("long", "short")
        for name in order:
            block = next(extra[name])
            started = time.perf_counter()
            watchers[name].add(block)
            added = time.perf_counter()
            watchers[name].refresh()
            refreshed = time.perf_counter()
            times[name] = (added - started, refreshed - added)
        adds.append(times["long"][0] / times["short"][0])
        refreshes.append(times["long"][1] / times["short"][1])
        if round_ % 10 == 0:
            lstsq = {}
            for name, matrix in (("short", short_matrix), ("long", long_matrix))[:: 1 if round_ % 20 else -1]:
                started = time.perf_counter()
                np.linalg.lstsq(matrix[:, :-1], matrix[:, -1], rcond=None)
                lstsq[name] = time.perf_counter() - started
            baseline.append(lstsq["long"] / lstsq["short"])
    print(f"A Watcher fed {minutes} minutes of a 1 kHz arm against one fed 1 minute, {rounds} interleaved rounds "
          f"of a 20 ms block and a refresh (ratios long / short, min / median / max):")
    print(f"  refresh                      {spread(refreshes)}")
    print(f"  add (20 ms block)            {spread(adds)}")
    print(f"  numbers held (state_size)    {long.state_size / short.state_size:.2f}  "
          f"({short.state_size} and {long.state_size})")
    print(f"  bytes allocated and kept     {long_bytes / short_bytes:.2f}  ({short_bytes} and {long_bytes})")
    print(f"  baseline, lstsq of every decimated row so far ({len(short_matrix)} and {len(long_matrix)} rows): "
          f"{spread(baseline)}")


if __name__ == "__main__":
    arguments = [int(value) for value in sys.argv[1:3]]
    main(*(arguments + [60, 300][len(arguments):]))
