"""map_in_threads: the same results as a loop, in order, with the caller's numpy error state and exceptions."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from jointid import threads
from jointid.threads import map_in_threads, threads_for


def test_results_come_in_the_items_order_from_more_than_one_thread(monkeypatch):
    monkeypatch.setattr(threads.os, "cpu_count", lambda: 2)
    started, names = threading.Barrier(2, timeout=30), []

    def square(value: int) -> int:
        if value < 2:
            started.wait()  # both first pieces run at once, or this times out
        names.append(threading.current_thread().name)
        return value * value

    assert map_in_threads(square, range(6)) == [0, 1, 4, 9, 16, 25]
    assert len(set(names)) == 2 and all(name.startswith("jointid") for name in names)


def test_one_core_runs_every_piece_in_the_callers_thread(monkeypatch):
    monkeypatch.setattr(threads.os, "cpu_count", lambda: 1)
    assert map_in_threads(lambda _: threading.current_thread().name, range(3)) == [threading.current_thread().name] * 3


@pytest.mark.parametrize("pieces, cores, expected", [(1, 8, 1), (3, 2, 2), (8, 8, 4), (5, None, 1)])
def test_threads_are_one_per_core_at_most_four_and_no_more_than_the_pieces(monkeypatch, pieces, cores, expected):
    monkeypatch.setattr(threads.os, "cpu_count", lambda: cores)
    assert threads_for(pieces) == expected


def test_the_callers_numpy_error_state_holds_in_every_piece(monkeypatch):
    """The command line's strict arithmetic: an overflow in a piece raises there as it would in the caller."""
    monkeypatch.setattr(threads.os, "cpu_count", lambda: 2)
    with np.errstate(over="raise"):
        with pytest.raises(FloatingPointError):
            map_in_threads(lambda value: np.float64(value) * 1e308, [1.0, 10.0])
    with np.errstate(over="ignore"):
        assert map_in_threads(lambda value: np.float64(value) * 1e308, [1.0, 10.0])[1] == np.inf
