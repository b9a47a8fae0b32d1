"""README.md stays one page that a fresh machine can follow literally, and CI runs what it says.

Its examples are run by tests/cli/test_doc_examples.py; this checks the page's shape: its length, that its test
command is the one .ci/run runs first, that every snippet uses the set-up's virtual environment and names the
extras where they are needed, and that each kind of user's path leads to a page that exists.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")
CI = (ROOT / ".ci" / "run").read_text(encoding="utf-8")

MOST_LINES = 150
"""One page (issue 31: it had grown to 237 lines)."""

PATHS = ("A student at the explorer", "An engineer with a log", "An FRC team with a SysId log",
         "A teacher serving a class", "Someone writing Python")
"""The kinds of user, each with a section of its own."""


def code_lines(text: str) -> list[str]:
    """The lines of the indented code blocks (four spaces after a blank line or another such line)."""
    lines, inside, previous_blank = [], False, True
    for line in text.splitlines():
        inside = line.startswith("    ") and (inside or previous_blank)
        if inside:
            lines.append(line[4:].removeprefix("$ "))
        previous_blank = not line.strip()
    return lines


def test_the_readme_is_one_page():
    assert len(README.splitlines()) <= MOST_LINES


def test_ci_runs_the_readmes_test_command_first():
    test_command = next(line for line in code_lines(README) if "pytest" in line)
    venv, install, run = test_command.split(" && ")
    ci_lines = [line.strip().removesuffix(" || exit 1") for line in CI.splitlines()
                if line.strip() and not line.lstrip().startswith("#")]
    assert venv in ci_lines
    pip = next(line for line in ci_lines if ".venv/bin/pip install" in line)
    assert install.split()[:2] == pip.split()[:2] and install.split()[-2:] == pip.split()[-2:]  # quiet flags aside
    first_pytest = next(line for line in ci_lines if "pytest" in line and "collected" not in line)
    assert first_pytest == run
    assert f"OPENBLAS_CORETYPE=Prescott {run}" in CI  # and again on another CPU's kernels


def test_every_test_left_out_of_cis_second_run_exists():
    # A renamed file would silently rejoin the run, but a misspelt one would leave its tests out unseen.
    ignored = re.findall(r"--ignore=(\S+)", CI)
    assert ignored and all((ROOT / path).is_file() for path in ignored), ignored


def test_every_snippet_uses_the_set_ups_environment_and_names_its_extra():
    pages = {"README.md": README, "docs/serve.md": (ROOT / "docs" / "serve.md").read_text(encoding="utf-8")}
    for name, text in pages.items():
        for line in code_lines(text):
            words = line.split()
            if words and words[0] in ("jointid", "pip", "python", "pytest"):
                raise AssertionError(f"{name}: `{line}` runs outside the set-up's .venv")
            assert " pip install" not in f" {line}" or ".venv/bin/pip install" in line, f"{name}: {line}"
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]["optional-dependencies"]
    for extra in ("report", "web", "ros", "wpilib"):
        assert extra in extras
        assert f".venv/bin/pip install -e '.[{extra}]'" in README, extra


def test_each_kind_of_user_has_a_path_to_a_page_that_exists():
    sections = re.split(r"^## ", README, flags=re.MULTILINE)
    for path in PATHS:
        section = next((s for s in sections if s.startswith(path)), None)
        assert section is not None, f"no section '## {path}'"
        pages = re.findall(r"\]\((docs/[\w.-]+\.md)", section)
        assert pages, f"{path}: points to no page in docs/"
    for link in re.findall(r"\]\(([^)#]+)", README):
        assert (ROOT / link).exists(), link
