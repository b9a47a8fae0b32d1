"""Where the real pendulum's measured runs are: ../shared/real-logs beside the checkout (CI places it there)."""

from __future__ import annotations

from pathlib import Path

import pytest

_CHECKOUT = Path(__file__).resolve().parents[2]
# Beside the checkout as CI places it, or beside the folder of a checkout made by `git worktree add` (/work/wt/NAME).
REAL_LOGS = next((folder for folder in (_CHECKOUT.parent / "shared" / "real-logs",
                                        _CHECKOUT.parent.parent / "shared" / "real-logs") if folder.is_dir()),
                 _CHECKOUT.parent / "shared" / "real-logs")
"""The folder of the three measured runs and their README."""


def reference_pipeline():
    """benchmarks/real_logs_reference/pipeline.py: the numpy/scipy reference of the real-log pipeline."""
    import importlib.util

    path = Path(__file__).resolve().parents[2] / "benchmarks" / "real_logs_reference" / "pipeline.py"
    spec = importlib.util.spec_from_file_location("real_logs_reference", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


needs_real_logs = pytest.mark.skipif(not REAL_LOGS.is_dir(), reason="../shared/real-logs is not beside the checkout")
"""Marks a test (or a module, as pytestmark) that reads the real runs."""
