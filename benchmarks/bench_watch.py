"""Live identification's cost against the time watched: a simulated arm at 1 kHz fed to a Watcher in 20 ms blocks
(a NetworkTables poll's worth), refreshed five times a second, for MINUTES minutes.
Refreshes before the first judged one (the warm-up, the first batches) cost less and are not counted.

Per minute it records each refresh's time, the time to take each block, the Watcher's state (numbers held) and the
process's resident set. It prints, as ratios of the last minute to the first (flat is 1.0), the min / median / max
over the last minute's refreshes (and blocks) divided by the first minute's median, and the state and resident
set at the end of each. Beside them, the baseline a user would write instead, numpy.linalg.lstsq over every
decimated row so far at each minute's end: its last-to-first ratio grows with the minutes.

    PYTHONPATH=. .venv/bin/python benchmarks/bench_watch.py [MINUTES]     (default 10)
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from jointid.live.received import Received  # noqa: E402
from jointid.studies.watch import Watcher  # noqa: E402

RATE = 1000.0
BLOCK = 20
"""Samples per block: 20 ms at 1 kHz."""
REFRESH_EVERY = 10
"""Blocks between refreshes: five a second."""
G = 9.81


def arm_minute(minute: int, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """One minute of a simulated arm (sum of sines, Coulomb friction, bias, Gaussian torque noise) at 1 kHz."""
    t = (minute * 60 * RATE + np.arange(int(60 * RATE))) / RATE
    motion = [(0.8, 0.3, 0.0), (0.4, 0.7, 1.0), (0.2, 1.3, 2.0)]
    q = sum(a * np.sin(2 * np.pi * f * t + p) for a, f, p in motion)
    qd = sum(a * 2 * np.pi * f * np.cos(2 * np.pi * f * t + p) for a, f, p in motion)
    qdd = sum(-a * (2 * np.pi * f) ** 2 * np.sin(2 * np.pi * f * t + p) for a, f, p in motion)
    tau = 0.05 * qdd + 0.3 * G * np.cos(q) + 0.1 * qd + 0.2 * np.sign(qd) + 0.2 + 0.5 * rng.standard_normal(len(t))
    return {"t": t, "q": q, "tau": tau, "qd": qd, "qdd": qdd}


def resident_bytes() -> int:
    """The process's resident set now (bytes)."""
    with open("/proc/self/statm") as status:
        return int(status.read().split()[1]) * 4096


def ratios(last: list[float], first: list[float]) -> str:
    """min / median / max of the last minute's values over the first minute's median."""
    base = statistics.median(first)
    values = sorted(value / base for value in last)
    return f"{values[0]:.2f} / {statistics.median(values):.2f} / {values[-1]:.2f}"


def main(minutes: int) -> None:
    """Watch `minutes` minutes and print the ratios."""
    rng = np.random.default_rng(3)
    watcher = Watcher()
    refresh_times, block_times, states, resident, baseline = [], [], [], [], []
    rows = []
    for minute in range(minutes):
        samples = arm_minute(minute, rng)
        refreshes, blocks = [], []
        for k, first in enumerate(range(0, len(samples["t"]), BLOCK)):
            block = Received({name: samples[name][first:first + BLOCK] for name in ("t", "q", "tau")})
            started = time.perf_counter()
            watcher.add(block)
            blocks.append(time.perf_counter() - started)
            if (k + 1) % REFRESH_EVERY == 0:
                started = time.perf_counter()
                refresh = watcher.refresh()
                elapsed = time.perf_counter() - started
                if refresh.parameters and refresh.parameters[0].verdict is not None:  # judged: the full cost
                    refreshes.append(elapsed)
        refresh_times.append(refreshes)
        block_times.append(blocks)
        states.append(watcher.state_size)
        resident.append(resident_bytes())
        # The baseline: every decimated row kept and refitted by lstsq (the regressor a user would build).
        step = watcher.filter.decimation
        s = {name: samples[name][::step] for name in samples}
        rows.append(np.column_stack([s["qdd"], G * np.cos(s["q"]), s["qd"], np.sign(s["qd"]),
                                     np.ones_like(s["q"]), s["tau"]]))
        every = np.vstack(rows)
        started = time.perf_counter()
        np.linalg.lstsq(every[:, :-1], every[:, -1], rcond=None)
        baseline.append(time.perf_counter() - started)
        print(f"minute {minute + 1}: refresh median {statistics.median(refreshes) * 1e3:.2f} ms, "
              f"state {watcher.state_size} numbers", flush=True)
    print(f"\n{minutes} minutes at {RATE:g} Hz, blocks of {BLOCK}, {1000 // (BLOCK * REFRESH_EVERY) * 1:g} "
          f"refreshes a second (ratios last minute / first minute, min / median / max):")
    print(f"  refresh time          {ratios(refresh_times[-1], refresh_times[0])}")
    print(f"  block (add) time      {ratios(block_times[-1], block_times[0])}")
    print(f"  state (numbers held)  {states[-1] / states[0]:.2f}  (first {states[0]}, largest {max(states)})")
    print(f"  resident set          {resident[-1] / resident[0]:.2f}")
    print(f"  baseline: lstsq of every row so far, last / first minute {baseline[-1] / baseline[0]:.1f}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 10)
