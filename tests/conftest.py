"""Shared test set-up: SVG snapshots live in the top-level snapshots/ directory."""

from __future__ import annotations

from pathlib import Path

import pytest_textual_snapshot

SNAPSHOT_DIR = Path(__file__).resolve().parent.parent / "snapshots"
"""Pinned SVG screenshots (one folder per test module) and pinned readout texts."""


def _snapshot_dirname(cls, *, test_location) -> str:
    """snapshots/<test module>/ instead of the plugin's tests/__snapshots__/<test module>/."""
    return str(SNAPSHOT_DIR / test_location.basename)


# The plugin hard-codes its extension class in the snap_compare fixture, so the
# directory can only be moved by overriding the class's dirname.
pytest_textual_snapshot.SVGImageExtension.dirname = classmethod(_snapshot_dirname)
