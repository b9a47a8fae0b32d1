"""The lesson's repeatable bounded torque noise, vectorised.

The sequential recurrence is seed <- (1664525*seed + 1013904223) mod 2^32,
drawn before each sample, and the error is noise*(2*seed/2^32 - 1). After k
steps seed_k = A_k*seed + C_k (mod 2^32), so the coefficients (A_k, C_k) are
computed once by doubling and serve every seed: no Python loop per sample.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

MULTIPLIER = 1664525
INCREMENT = 1013904223
MODULUS = 2**32
_MASK = np.uint64(MODULUS - 1)


@lru_cache(maxsize=4)
def _jump_coefficients(count: int) -> tuple[np.ndarray, np.ndarray]:
    """(A_k, C_k) for k = 1..count as uint64 arrays with seed_k = A_k*seed + C_k mod 2^32."""
    a = np.empty(count, dtype=np.uint64)
    c = np.empty(count, dtype=np.uint64)
    if count == 0:
        return a, c
    a[0], c[0] = MULTIPLIER, INCREMENT
    filled = 1
    while filled < count:
        take = min(filled, count - filled)
        step_a, step_c = a[filled - 1], c[filled - 1]  # the map of `filled` steps
        # seed_{k+filled} = step_a*seed_k + step_c. Factors are below 2^32, so the
        # uint64 products (and the added increment) cannot overflow.
        a[filled : filled + take] = (step_a * a[:take]) & _MASK
        c[filled : filled + take] = (step_a * c[:take] + step_c) & _MASK
        filled += take
    a.setflags(write=False)
    c.setflags(write=False)
    return a, c


def lcg_states(seeds, count: int) -> np.ndarray:
    """Generator states after 1..count steps for each seed: shape (count,) or (K, count) for K seeds."""
    a, c = _jump_coefficients(count)
    seeds = np.asarray(seeds, dtype=np.uint64)
    return (seeds[..., None] * a + c) & _MASK


def torque_noise(bound: float, count: int, seed: int | np.ndarray) -> np.ndarray:
    """Errors noise*(2*state/2^32 - 1) in [-bound, bound), one per sample; (count,) or (K, count)."""
    return bound * (2.0 * lcg_states(seed, count).astype(float) / MODULUS - 1.0)
