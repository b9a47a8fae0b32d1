"""Start-up: help never loads numpy, and `import jointid` loads its public names only on first use."""

import json
import subprocess
import sys

import pytest

import jointid
from jointid.cli import SUBCOMMANDS

HEAVY = ("numpy", "scipy", "pandas", "importlib.metadata")
"""Modules that printing help has no use for: numpy alone is most of a cold start."""


def heavy_modules_after(code: str, watched: tuple[str, ...] = HEAVY) -> tuple[str, list[str]]:
    """(stdout, the `watched` modules loaded, HEAVY by default) after running `code` in a fresh interpreter."""
    probe = (
        "import contextlib, io, json, sys\n"
        "out = io.StringIO()\n"
        "with contextlib.redirect_stdout(out):\n"
        "    try:\n"
        f"        {code}\n"
        "    except SystemExit as exit:\n"
        "        assert exit.code in (0, None), exit.code\n"
        f"print(json.dumps([out.getvalue(), sorted(m for m in sys.modules if m in {watched!r})]))\n"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    return tuple(json.loads(done.stdout))


@pytest.mark.parametrize("command", [[]] + [[name] for name in SUBCOMMANDS],
                         ids=lambda command: " ".join(command) or "jointid")
def test_help_loads_no_numpy(command):
    text, loaded = heavy_modules_after(f"from jointid.cli import main; main({command + ['--help']!r})")
    assert text.startswith("usage: jointid") and loaded == []


def test_help_loads_neither_typing_nor_shutil():
    """typing (2.5 ms) and shutil (zlib, bz2, lzma: 2 ms) are a tenth of a --help's start beyond Python's own."""
    text, loaded = heavy_modules_after("from jointid.cli import main; main(['serve', '--help'])",
                                       ("typing", "shutil", "lzma"))
    assert text.startswith("usage: jointid serve") and loaded == []
    _, loaded = heavy_modules_after("import shutil; from jointid.cli import main; main(['serve', '--help'])",
                                    ("typing", "shutil", "lzma"))
    assert loaded == ["lzma", "shutil"]  # the check can fail


def test_a_plain_fit_loads_neither_statistics_nor_the_motor_tables(tmp_path):
    """A fit's 95 % intervals need no statistics (fractions, decimal, random), and a log's fit without a motor
    neither the motor tables nor the gains; with a motor it does. The log is fitted like for like: the robust step
    and the omitted-terms test take other levels, from statistics."""
    watched = ("statistics", "fractions", "jointid.model.motors", "jointid.studies.gains")
    text, loaded = heavy_modules_after("from jointid.cli import main; main(['fit', '--json'])", watched)
    assert json.loads(text)["rank"] == 3 and loaded == []
    log = tmp_path / "log.csv"
    log.write_text("t,q,qd,qdd,tau\n" + "".join(f"{i / 100},{i % 7 / 10},{i % 5 / 10},{i % 3 / 10},{i % 11 / 10}\n"
                                                 for i in range(200)))
    fit = (f"from jointid.cli import main; main(['fit', '--csv', {str(log)!r}, '--json', '--model', 'plain', "
           "'--no-robust', '--cutoff', '0'")
    text, loaded = heavy_modules_after(fit + "])", watched)
    assert "estimate" in json.loads(text) and loaded == []
    _, loaded = heavy_modules_after(fit + ", '--motor', 'NEO', '--gear', '50'])", watched)
    assert "jointid.model.motors" in loaded


def test_the_help_test_sees_numpy_when_a_command_runs():
    # The check above must be able to fail: running a fit does load numpy.
    text, loaded = heavy_modules_after("from jointid.cli import main; main(['fit', '--json'])")
    assert json.loads(text)["rank"] == 3 and "numpy" in loaded


def test_every_subcommand_module_defines_the_name_it_is_listed_under():
    from jointid.cli import subcommand

    for name in SUBCOMMANDS:
        assert subcommand(name).NAME == name


def test_import_jointid_loads_no_numpy_until_a_name_is_used():
    _, loaded = heavy_modules_after("import jointid")
    assert loaded == []
    _, loaded = heavy_modules_after("import jointid; jointid.fit_joint")
    assert "numpy" in loaded


def test_every_public_name_resolves_to_the_object_its_module_defines():
    from jointid.estimation import fit, solver
    from jointid.model import terms as model
    from jointid.synthetic import settings

    for name in jointid.__all__:
        assert getattr(jointid, name) is not None, name
    assert jointid.fit_joint is fit.fit_joint and jointid.PLAIN is model.PLAIN
    assert jointid.Settings is settings.Settings and jointid.solve_least_squares is solver.solve_least_squares
    assert set(jointid.__all__) <= set(dir(jointid))
    with pytest.raises(AttributeError, match="no attribute 'not_a_name'"):
        jointid.not_a_name  # noqa: B018


def test_the_choices_name_the_motions_the_numeric_modules_define():
    from jointid.model.terms import EXTRA_TERMS
    from jointid.options import ALL_MOTION_NAMES, EXTRA_TERM_NAMES, TRAINING_MOTION_NAMES
    from jointid.synthetic.motions import ALL_MOTIONS, TRAINING_MOTIONS

    assert tuple(TRAINING_MOTIONS) == TRAINING_MOTION_NAMES
    assert tuple(ALL_MOTIONS) == ALL_MOTION_NAMES
    assert tuple(EXTRA_TERMS) == EXTRA_TERM_NAMES
