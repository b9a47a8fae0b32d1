"""Shared test set-up: SVG snapshots live in the top-level snapshots/ directory."""

from __future__ import annotations

from importlib import metadata
from pathlib import Path

import pytest
import pytest_textual_snapshot

SNAPSHOT_DIR = Path(__file__).resolve().parents[1] / "snapshots"
"""Pinned SVG screenshots (one folder per test module) and pinned readout texts."""

SNAPSHOT_PLUGIN_VERSION = "1.1.0"
"""The pytest-textual-snapshot release whose extension class `move_snapshot_dir` overrides."""


def _snapshot_dirname(cls, *, test_location) -> str:
    """snapshots/<test module>/ instead of the plugin's tests/__snapshots__/<test module>/."""
    return str(SNAPSHOT_DIR / test_location.basename)


def move_snapshot_dir() -> None:
    """Keep SVG snapshots in snapshots/ by overriding the plugin's extension `dirname`.

    The plugin hard-codes its extension class in the snap_compare fixture, so
    the directory can only be moved on the class. Another plugin release may
    look its directory up differently and would silently compare against (or
    write) tests/__snapshots__, so any other version stops the run.
    """
    version = metadata.version("pytest-textual-snapshot")
    if version != SNAPSHOT_PLUGIN_VERSION:
        raise pytest.UsageError(
            f"tests/conftest.py moves SVG snapshots to snapshots/ by overriding "
            f"pytest-textual-snapshot {SNAPSHOT_PLUGIN_VERSION}'s SVGImageExtension.dirname; "
            f"{version} is installed. Install {SNAPSHOT_PLUGIN_VERSION} (pyproject.toml pins it) "
            f"or check the override against the new release."
        )
    pytest_textual_snapshot.SVGImageExtension.dirname = classmethod(_snapshot_dirname)


def pytest_configure(config) -> None:
    """Check the snapshot plugin's version and move its directory before any test is collected."""
    move_snapshot_dir()
