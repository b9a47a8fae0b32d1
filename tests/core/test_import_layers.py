"""The core's import contracts (pyproject.toml's [tool.importlinter]): one direction of imports, no circles.

import-linter checks them on the package as it is, and on a copy in which a
result module imports the presentation layer, to show the check can fail.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
LINT_IMPORTS = Path(sys.executable).parent / "lint-imports"


def lint_imports(source_root: Path, config: Path) -> subprocess.CompletedProcess:
    """`lint-imports` on the jointid package found under `source_root`."""
    return subprocess.run([str(LINT_IMPORTS), "--config", str(config), "--no-cache"], capture_output=True,
                          text=True, cwd=source_root, env={"PYTHONPATH": str(source_root), "PATH": ""})


def copy_of_the_core(tmp_path: Path) -> Path:
    """jointid/ and pyproject.toml copied under tmp_path, without bytecode."""
    shutil.copytree(ROOT / "jointid", tmp_path / "jointid", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    return tmp_path


def test_the_core_keeps_its_layers_and_has_no_import_circles():
    done = lint_imports(ROOT, ROOT / "pyproject.toml")
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Contracts: 2 kept, 0 broken." in done.stdout


def test_a_result_that_imports_presentation_breaks_the_layers(tmp_path):
    copy = copy_of_the_core(tmp_path)
    fit = copy / "jointid" / "estimation" / "fit.py"
    fit.write_text(fit.read_text() + "\nfrom ..present.status import status_message  # an up-call\n")
    done = lint_imports(copy, copy / "pyproject.toml")
    assert done.returncode == 1
    assert "one way" in done.stdout and "BROKEN" in done.stdout
    assert "jointid.estimation.fit -> jointid.present.status" in done.stdout


def test_a_circle_between_two_modules_of_one_stage_is_found(tmp_path):
    copy = copy_of_the_core(tmp_path)
    solver = copy / "jointid" / "estimation" / "solver.py"
    solver.write_text(solver.read_text() + "\nfrom . import uncertainty  # uncertainty imports the solver\n")
    done = lint_imports(copy, copy / "pyproject.toml")
    assert done.returncode == 1
    assert "No import circles anywhere in jointid BROKEN" in done.stdout
