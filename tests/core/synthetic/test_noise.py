"""The vectorised noise generator against the lesson's sequential recurrence."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from jointid.synthetic.noise import lcg_states, torque_noise


def sequential_states(seed: int, count: int) -> list[int]:
    """The lesson's recurrence, one step at a time."""
    states = []
    for _ in range(count):
        seed = (1664525 * seed + 1013904223) % 2**32
        states.append(seed)
    return states


@settings(max_examples=200, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), count=st.integers(0, 3000))
def test_states_are_bit_identical_to_the_recurrence(seed, count):
    assert lcg_states(seed, count).tolist() == sequential_states(seed, count)


def test_many_seeds_at_once_match_one_seed_at_a_time():
    seeds = np.array([0, 1, 7, 2**31, 2**32 - 1, 123456789])
    together = lcg_states(seeds, 257)
    assert together.shape == (6, 257)
    for row, seed in zip(together, seeds):
        assert row.tolist() == sequential_states(int(seed), 257)


def test_long_sequence_matches_at_its_end():
    count = 1_000_003
    assert lcg_states(7, count)[-3:].tolist() == sequential_states(7, count)[-3:]


def test_noise_values_follow_the_lesson_formula_and_stay_in_bounds():
    states = sequential_states(7, 50)
    expected = [0.2 * (2 * s / 2**32 - 1) for s in states]
    values = torque_noise(0.2, 50, 7)
    assert values.tolist() == expected
    assert np.all(np.abs(torque_noise(0.5, 10_000, 3)) <= 0.5)


def test_zero_bound_gives_exact_zeros():
    assert not np.any(torque_noise(0.0, 100, 7))
