"""Third-party internals are adapted in tui/third_party/ only, switched on when the app starts, and
fall back to the stock path on other versions."""

from __future__ import annotations

import asyncio
import json
import re
import subprocess
import sys
from importlib import metadata
from pathlib import Path

import pytest
from plotext import _matrix as plotext_matrix
from plotext import _utility as plotext_utility
from support.tui_support import make_app

from jointid.cli.version import version_text
from tui.ranges import NOISE_RANGE
from tui.third_party import adapter as third_party
from tui.third_party import plotext_speedups
from tui.widgets.stepper import Stepper
from tui.widgets.torque_plot import TorquePlot

ROOT = Path(__file__).resolve().parents[2]


def plotext_functions() -> dict:
    """The functions plotext calls that the adapter replaces, as plotext looks them up now."""
    return {"hd_group": plotext_utility.hd_group, "join": plotext_utility.join,
            "set_matrices": plotext_matrix.matrix_class.set_matrices,
            "insert_element": plotext_matrix.matrix_class.insert_element,
            "get_matrix_data": plotext_utility.get_matrix_data}


@pytest.fixture(autouse=True)
def fresh_check():
    """Each test starts before any activation; afterwards the next app start checks the real versions again."""
    third_party.uninstall()
    yield
    third_party.uninstall()


def pretend_installed(monkeypatch, **versions: str | None) -> None:
    """Make the version reader report other versions (keyword: distribution with _ for -)."""
    real = third_party.installed_version
    fake = {name.replace("_", "-"): version for name, version in versions.items()}
    monkeypatch.setattr(third_party, "installed_version",
                        lambda name: fake[name] if name in fake else real(name))


def test_importing_the_app_patches_nothing():
    code = (
        "import json, plotext._utility as u, plotext._matrix as m\n"
        "from textual.screen import ModalScreen as S\n"
        "before = [u.hd_group, u.join, m.matrix_class.set_matrices, S._on_message, S.dismiss]\n"
        "import tui.widgets.torque_plot, tui.widgets.charts, tui.widgets.stepper, tui.app\n"
        "from tui.third_party import adapter as third_party\n"
        "after = [u.hd_group, u.join, m.matrix_class.set_matrices, S._on_message, S.dismiss]\n"
        "print(json.dumps([all(a is b for a, b in zip(before, after)),\n"
        "                  [third_party.active(a.key) for a in third_party.ADAPTERS]]))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    unchanged, active = json.loads(done.stdout)
    assert unchanged
    assert active == [False] * len(third_party.ADAPTERS)


def test_activation_installs_the_fast_helpers_once_and_uninstall_restores_plotexts_own():
    assert plotext_functions() == plotext_speedups.ORIGINALS
    lines = third_party.activate()
    assert plotext_functions() == plotext_speedups.FAST
    assert all(third_party.active(adapter.key) for adapter in third_party.ADAPTERS)
    assert third_party.activate() == lines  # a second start changes nothing
    assert plotext_functions() == plotext_speedups.FAST
    third_party.uninstall()
    assert plotext_functions() == plotext_speedups.ORIGINALS
    assert not any(third_party.active(adapter.key) for adapter in third_party.ADAPTERS)
    third_party.uninstall()  # twice is harmless too
    assert plotext_functions() == plotext_speedups.ORIGINALS


def modal_methods() -> tuple:
    """ModalScreen's message dispatch and dismiss, as Textual looks them up now."""
    from textual.screen import ModalScreen

    return ModalScreen._on_message, ModalScreen.dismiss


def test_activation_installs_the_burst_guard_on_modal_screens_and_uninstall_takes_it_off():
    from textual.message_pump import MessagePump
    from textual.screen import Screen

    stock = (MessagePump._on_message, Screen.dismiss)
    assert modal_methods() == stock
    third_party.activate()
    assert third_party.active(third_party.MODAL_BURSTS) and modal_methods() != stock
    third_party.uninstall()
    assert modal_methods() == stock


def test_another_textual_keeps_the_stock_modal_screens_and_says_so(monkeypatch):
    from textual.message_pump import MessagePump
    from textual.screen import Screen

    pretend_installed(monkeypatch, textual="9.0.0")
    lines = third_party.activate()
    assert not third_party.active(third_party.MODAL_BURSTS)
    assert modal_methods() == (MessagePump._on_message, Screen.dismiss)
    assert lines[3] == "textual 9.0.0 (expected 8.2.8): stock modal screens (Enter Enter can close one twice " \
                       "and end the app)"


def test_status_lines_name_the_installed_versions():
    lines = third_party.activate()
    assert lines == third_party.status()
    assert lines == [
        "plotext 5.3.2: fast chart helpers active",
        "plotext 5.3.2, textual-plotext 1.0.1: direct chart strips active",
        "textual 8.2.8: repaint-only number fields active",
        "textual 8.2.8: modal screens safe from key bursts",
        "textual 8.2.8: one notification per title",
        "textual 8.2.8: paths in notifications wrap between folders",
    ]
    for name, version in third_party.PINNED.items():
        assert metadata.version(name) == version  # the pins match pyproject.toml's


def test_another_plotext_keeps_the_stock_functions_and_says_so(monkeypatch):
    pretend_installed(monkeypatch, plotext="5.4.0")
    lines = third_party.activate()
    assert plotext_functions() == plotext_speedups.ORIGINALS
    assert not third_party.active(third_party.PLOTEXT_HELPERS)
    assert not third_party.active(third_party.CHART_MATRIX)
    assert third_party.active(third_party.NUMBER_FIELDS)
    assert lines[0] == "plotext 5.4.0 (expected 5.3.2): stock chart helpers"
    assert lines[1] == "plotext 5.4.0 (expected 5.3.2), textual-plotext 1.0.1: stock chart rendering " \
                       "(PlotextPlot.render, slower)"


def test_a_missing_package_is_reported_as_not_installed(monkeypatch):
    pretend_installed(monkeypatch, textual=None)
    assert third_party.status()[2] == "textual not installed (expected 8.2.8): stock number fields " \
                                      "(a new value relayouts the screen)"
    assert third_party.activate() == third_party.status()
    assert not third_party.active(third_party.NUMBER_FIELDS)


def chart_cells(app) -> list[list[tuple[str, object]]]:
    """Every torque plot's cells as (character, Rich style), line by line."""
    cells = []
    for plot in app.screen.query(TorquePlot):
        for y in range(plot.size.height):
            cells.append([(character, segment.style)
                          for segment in plot.render_line(y) for character in segment.text])
    return cells


def test_the_stock_paths_draw_the_same_charts_and_the_fields_still_work(monkeypatch):
    """On other versions the charts come from PlotextPlot.render and the fields from Input's watcher."""

    async def main():
        app = make_app()
        async with app.run_test(size=(120, 40)) as pilot:
            await pilot.pause()
            charts = chart_cells(app)
            stepper = app.screen.query_one("#noise", Stepper)
            stepper.focus()
            await pilot.press("right")
            await pilot.pause()
            return charts, stepper.value, app.screen.settings.noise, third_party.status()

    fast_charts, *fast_rest, _ = asyncio.run(main())
    third_party.uninstall()
    pretend_installed(monkeypatch, plotext="5.4.0", textual_plotext="1.1.0", textual="8.3.0")
    stock_charts, *stock_rest, stock_status = asyncio.run(main())
    assert all(": stock " in line for line in stock_status)
    assert plotext_functions() == plotext_speedups.ORIGINALS
    assert len(stock_charts) > 20 and stock_charts == fast_charts
    assert stock_rest == fast_rest == [NOISE_RANGE.format(NOISE_RANGE.step), NOISE_RANGE.step]


def test_jointid_version_prints_the_stack_and_the_adapters():
    done = subprocess.run([sys.executable, "-m", "jointid", "--version"], capture_output=True, text=True,
                          cwd=ROOT)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[0] == f"jointid {metadata.version('jointid')}"
    for name in ("numpy", "textual", "textual-plotext", "plotext"):
        assert f"{name} {metadata.version(name)}" in lines
    assert "  plotext 5.3.2: fast chart helpers active" in lines


def test_jointid_version_imports_no_ui_package():
    code = (
        "import json, sys\nfrom jointid.cli import main\n"
        "try:\n    main(['--version'])\nexcept SystemExit as exit:\n    status = exit.code\n"
        "print(json.dumps([status, sorted(m for m in sys.modules "
        "if m.split('.')[0] in {'textual', 'plotext', 'rich', 'textual_plotext'})]))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    status, loaded = json.loads(done.stdout.splitlines()[-1])
    assert (status, loaded) == (0, [])


def test_jointid_version_without_the_ui_packages(monkeypatch):
    real = metadata.version

    def without_ui(name):
        if name in third_party.PINNED:
            raise metadata.PackageNotFoundError(name)
        return real(name)

    monkeypatch.setattr(metadata, "version", without_ui)
    monkeypatch.setattr(third_party, "_version_beside_package", lambda name: None)  # no dist-info folders either
    text = version_text()
    assert "textual not installed" in text.splitlines()
    assert "  plotext not installed (expected 5.3.2): stock chart helpers" in text.splitlines()
    monkeypatch.setitem(sys.modules, "tui", None)  # and without the explorer's own package
    monkeypatch.delitem(sys.modules, "tui.third_party.adapter")
    monkeypatch.delitem(sys.modules, "tui.third_party")
    assert version_text().splitlines()[-1].startswith("explorer adapters: unavailable")


PRIVATE_NAMES = re.compile(
    r"\._set_sizes?\b|\._build_matrix\b|\._plot\b|\b_get_plotext_theme_name|\b_watch_value|\b_on_blur"
    r"|\b_suggestion|monitor\.matrix|\._compositor_refresh|\._layout_required|\._dirty_widgets"
    r"|\._repaint_required|plotext\._|from plotext import _"
)
"""plotext, textual-plotext and Textual private names the explorer uses (and plotext's private modules)."""

ADAPTER_MODULES = {"tui/third_party/adapter.py", "tui/third_party/plotext_speedups.py"}
"""The only files allowed to name them."""


def test_only_the_adapter_modules_touch_third_party_internals():
    offenders = []
    for path in sorted([*ROOT.glob("tui/**/*.py"), *ROOT.glob("benchmarks/*.py")]):
        relative = path.relative_to(ROOT).as_posix()
        if relative in ADAPTER_MODULES:
            continue
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if PRIVATE_NAMES.search(line):
                offenders.append(f"{relative}:{number}: {line.strip()}")
    assert offenders == []
