"""Start-up of the explorer: its first frame loads only what that frame shows.

The other views, the dialogs, the log readers, the designer and the heavy
libraries are imported when first opened (benchmarks/bench_tui_startup.py
measures the time; this pins the property, not a time).
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

DEFERRED = (
    # what other screens need
    "tui.screens.bag_joint", "tui.screens.design", "tui.screens.export", "tui.screens.help",
    "tui.screens.ladder", "tui.screens.loading", "tui.screens.matrix", "tui.screens.open_log",
    "tui.screens.physics", "tui.screens.residuals", "tui.screens.sweep", "tui.widgets.small_plots",
    # jointid beyond the synthetic fit
    "jointid.logs.bag", "jointid.logs.table", "jointid.studies.cross_excitation", "jointid.logs.derivatives", "jointid.studies.design",
    "jointid.studies.design_process", "jointid.files", "jointid.studies.ladder", "jointid.studies.log_fit", "jointid.estimation.low_pass",
    "jointid.estimation.residuals", "jointid.studies.sensitivity", "jointid.studies.simulation", "jointid.studies.sweep",
    # heavy libraries
    "scipy", "pandas", "rosbags", "importlib.metadata",
)
"""Modules the first frame of the explorer at the default settings has no use for."""

FIRST_FRAME = """
import json, sys
{before}
from tui.app import JointIdApp

class FirstFrame(JointIdApp):
    restore_gc = False

    def on_ready(self):
        super().on_ready()
        self.call_after_refresh(self.exit)

FirstFrame().run(headless=True, size=(120, 40))
print(json.dumps(sorted(name for name in sys.modules if name in {deferred!r})))
"""


def deferred_modules_loaded(before: str = "") -> list[str]:
    """The DEFERRED modules in sys.modules once a fresh explorer process drew its first frame."""
    code = FIRST_FRAME.format(before=before, deferred=DEFERRED)
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_the_first_frame_loads_no_other_view_log_reader_designer_or_heavy_library():
    assert deferred_modules_loaded() == []


def test_the_probe_sees_a_deferred_module_once_something_imports_it():
    # The check above must be able to fail.
    loaded = deferred_modules_loaded("import jointid.studies.log_fit, tui.screens.design")
    assert {"jointid.studies.log_fit", "tui.screens.design"} <= set(loaded)
