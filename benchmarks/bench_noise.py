"""Vectorised LCG noise against the lesson's one-step-at-a-time recurrence.

Run: .venv/bin/python benchmarks/bench_noise.py
Prints times and the speed-up ratio measured in this one process.
"""

import time

import numpy as np

from jointid.synthetic.noise import _jump_coefficients, torque_noise


def sequential_noise(bound: float, count: int, seed: int) -> list[float]:
    """The lesson's recurrence in plain Python, drawn before each sample."""
    values = []
    for _ in range(count):
        seed = (1664525 * seed + 1013904223) % 2**32
        values.append(bound * (2 * seed / 2**32 - 1))
    return values


def best_of(repeats: int, function) -> float:
    """Shortest wall time of `repeats` calls, in seconds."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    """Time one long sequence and many seeds, vectorised and sequential."""
    count = 1_000_000
    fresh = lambda: (_jump_coefficients.cache_clear(), torque_noise(0.2, count, 7))  # noqa: E731
    vector = best_of(5, fresh)
    loop = best_of(1, lambda: sequential_noise(0.2, count, 7))
    assert np.array_equal(torque_noise(0.2, count, 7), sequential_noise(0.2, count, 7))
    print(f"1,000,000 samples: vectorised {vector * 1e3:.1f} ms, sequential {loop * 1e3:.0f} ms, "
          f"ratio {loop / vector:.0f}x")

    seeds = np.arange(7, 7 + 10_000)
    vector = best_of(5, lambda: torque_noise(0.2, 24, seeds))
    loop = best_of(1, lambda: [sequential_noise(0.2, 24, int(s)) for s in seeds])
    print(f"10,000 seeds x 24 samples: vectorised {vector * 1e3:.2f} ms, sequential {loop * 1e3:.0f} ms, "
          f"ratio {loop / vector:.0f}x")


if __name__ == "__main__":
    main()
