"""Independent pieces of numpy work (FFTs, element-wise passes over a log's columns) on the machine's cores.

numpy releases the GIL inside its FFTs and ufunc loops, so threads run such work side by side: two 2^20-point
FFTs took half the time on two threads (benchmarks/README.md, "The log path"). Each piece runs in a copy of the
caller's context, so numpy's error state (`strict_arithmetic` on the command line) applies in it as in the caller.
"""

from __future__ import annotations

import contextvars
import os
from collections.abc import Callable, Iterable
from concurrent.futures import ThreadPoolExecutor

MAX_THREADS = 4
"""At most this many pieces at once: beyond it a log's few columns gain nothing and hold more memory at once."""


def threads_for(pieces: int) -> int:
    """How many threads `pieces` independent pieces get: one per core, at most MAX_THREADS and `pieces`."""
    return max(1, min(pieces, os.cpu_count() or 1, MAX_THREADS))


def map_in_threads(function: Callable, items: Iterable) -> list:
    """[function(item) for item in items], in that order, computed on up to threads_for(len(items)) threads; the
    first exception any call raises is raised here. One thread: in this one, with no pool."""
    items = list(items)
    workers = threads_for(len(items))
    if workers == 1:
        return [function(item) for item in items]
    context = contextvars.copy_context()
    # A pool per call, not one shared: a call made from inside a piece can never wait on its own pool.
    with ThreadPoolExecutor(max_workers=workers, thread_name_prefix="jointid") as pool:
        futures = [pool.submit(context.copy().run, function, item) for item in items]
        return [future.result() for future in futures]
