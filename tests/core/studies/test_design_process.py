"""Designs in a child process: the in-process result bit for bit; failures, kills and cancels reach the caller."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from support.design_stand_ins import broken_design, endless_design, gone, refused_design
from support.tui_support import time_limit

from jointid.studies.design import DesignCancelled, DesignError, DesignSpec, design_motion
from jointid.studies.design_process import DesignFailed, DesignProcess
from jointid.synthetic.settings import Settings

TESTS = str(Path(__file__).resolve().parents[2])  # tests/, where the support package is


def assert_same_design(mine, reference) -> None:
    """Every number of two DesignResults equal, bit for bit."""
    assert mine.motion == reference.motion
    np.testing.assert_array_equal(mine.motion.coefficients, reference.motion.coefficients)
    assert mine.criterion_value == reference.criterion_value and mine.converged == reference.converged
    for name in ("design", "rich"):
        a, b = getattr(mine, name), getattr(reference, name)
        np.testing.assert_array_equal(a.noise_bound_std_error, b.noise_bound_std_error)
        np.testing.assert_array_equal(a.relative_std_pct, b.relative_std_pct)
        assert a.condition_number == b.condition_number
    assert [(c.name, c.limit, c.peak) for c in mine.checks] == [(c.name, c.limit, c.peak) for c in reference.checks]
    assert mine.spec == reference.spec


def test_a_design_in_the_child_is_bit_identical_to_one_in_process_and_the_child_is_reused():
    specs = [DesignSpec(),
             DesignSpec(criterion="a", starts=3, experiment=Settings(noise=0.2, model="coulomb+bias"))]
    designer = DesignProcess()
    try:
        reports = []
        first = designer.run(specs[0], progress=lambda done, total: reports.append((done, total)))
        pid = designer.pid
        second = designer.run(specs[1])
        assert designer.pid == pid  # the same child served both
    finally:
        designer.close()
    assert gone(pid)
    assert_same_design(first, design_motion(specs[0]))
    assert_same_design(second, design_motion(specs[1]))
    assert reports[0] == (1, 8) and reports[-1] == (8, 8)  # the first start and the last are always reported


def test_a_refused_design_is_a_design_error_and_a_bug_a_one_line_design_failed():
    designer = DesignProcess(refused_design)
    try:
        with pytest.raises(DesignError, match="^no start found a motion within the limits"):
            designer.run(DesignSpec())
        designer.function = broken_design  # the next child runs the broken one
        designer.stop()
        with pytest.raises(DesignFailed) as failure:
            designer.run(DesignSpec())
    finally:
        designer.close()
    assert str(failure.value) == "the optimiser failed: ZeroDivisionError: division by zero"


def test_stop_from_another_thread_kills_a_running_design_at_once():
    designer = DesignProcess(endless_design)
    started = threading.Event()
    threading.Thread(target=lambda: (started.wait(), designer.stop()), daemon=True).start()
    with time_limit(60), pytest.raises(DesignCancelled):
        designer.run(DesignSpec(), progress=lambda done, total: started.set())
    assert designer.pid is None


def test_cancelled_kills_the_child_and_the_next_run_starts_a_fresh_one():
    designer = DesignProcess(endless_design)
    pids = []

    def cancelled() -> bool:
        pids.append(designer.pid)
        return len(pids) > 2

    with time_limit(60), pytest.raises(DesignCancelled):
        designer.run(DesignSpec(), cancelled=cancelled)
    killed = next(pid for pid in pids if pid is not None)
    assert gone(killed) and designer.pid is None
    designer.function = design_motion
    try:
        result = designer.run(replace(DesignSpec(), starts=1))
        assert designer.pid not in (None, killed)
    finally:
        designer.close()
    assert result.spec.starts == 1


def test_a_child_killed_by_someone_else_is_a_design_failed():
    designer = DesignProcess(endless_design)

    def kill_it(done, total):
        os.kill(designer.pid, signal.SIGKILL)

    with time_limit(60), pytest.raises(DesignFailed, match=r"^the optimiser's process stopped \(exit status -9\)$"):
        designer.run(DesignSpec(), progress=kill_it)


def test_a_child_whose_parent_dies_ends_itself():
    parent = textwrap.dedent(f"""
        import os, sys, threading
        sys.path[:0] = [{TESTS!r}]
        from support.design_stand_ins import endless_design
        from jointid.studies.design import DesignSpec
        from jointid.studies.design_process import DesignProcess

        designer = DesignProcess(endless_design)

        def report(done, total):
            print(designer.pid, flush=True)
            os._exit(0)  # the parent dies without a word to its child

        designer.run(DesignSpec(), progress=report)
    """)
    with time_limit(60):
        out = subprocess.run([sys.executable, "-c", parent], capture_output=True, text=True, check=True).stdout
        pid = int(out.split()[0])
        while not gone(pid):  # the orphan is re-parented; it ends at its next report (a second at most)
            time.sleep(0.05)
