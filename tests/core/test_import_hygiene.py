"""Boundaries: the core never drags in the user interface, and the UI's modules import in one direction."""

import ast
import json
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from support.import_check import packages_loaded

ROOT = Path(__file__).resolve().parents[2]
UI_PACKAGES = {"textual", "plotext", "rich", "tui", "textual_plotext"}


def test_import_jointid_loads_no_ui_packages():
    imports = "jointid, jointid.studies.experiment, jointid.present.documents, jointid.cli, jointid.cli.explorer_command"
    assert packages_loaded(imports, UI_PACKAGES) == []


def test_the_installed_command_hands_its_explorer_over_and_loads_no_ui_for_a_subcommand():
    # pip's `jointid` starts in tui.command, which passes the explorer to the core: no entry-point lookup
    # (importlib.metadata, a few per cent of the explorer's start); the core still imports nothing of the UI.
    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
    assert scripts["jointid"] == "tui.command:console_script"
    assert packages_loaded("tui.command", UI_PACKAGES) == ["tui", "tui.command"]
    probe = (
        "import json, sys\n"
        "import tui.entry\n"
        "def explore(settings, *rest):\n"
        "    print(json.dumps([settings.motion, 'importlib.metadata' in sys.modules]))\n"
        "    return 3\n"
        "tui.entry.explore = explore\n"
        "sys.argv = ['jointid', '--motion', 'rich']\n"
        "from tui.command import console_script\n"
        "console_script()\n"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, cwd=ROOT)
    assert (done.returncode, done.stderr) == (3, "")
    assert json.loads(done.stdout) == ["rich", False]


def test_fit_imports_no_scipy():
    # The 95 % interval's Student-t quantile is pure Python (jointid.estimation.student_t has the figure).
    assert packages_loaded("jointid.cli", {"scipy"}, run="jointid.cli.main(['fit', '--noise', '0.2', '--json'])") == []


def test_rosbags_is_imported_only_to_open_a_bag():
    # jointid[ros] is an optional extra: neither `import jointid` nor a fit without a bag may need it.
    imports = "jointid, jointid.cli, jointid.studies.log_fit, jointid.logs.request, jointid.cli.bag_info_command"
    assert packages_loaded(imports, {"rosbags"}) == []
    assert packages_loaded("jointid.cli", {"rosbags"}, run="jointid.cli.main(['fit', '--noise', '0.2', '--json'])") == []


def test_bag_info_command_module_imports_no_numpy_at_its_top_level():
    # Its --help must stay light: numpy, jointid.logs.bag and rosbags come only inside run() (the survey's shared
    # parser and printer, file_survey, likewise).
    for name in ("bag_info_command", "file_survey"):
        top = ast.parse((ROOT / f"jointid/cli/{name}.py").read_text()).body
        names = {alias.name if isinstance(node, ast.Import) else node.module
                 for node in top if isinstance(node, (ast.Import, ast.ImportFrom)) for alias in node.names}
        assert names <= {"__future__", "argparse", "arguments", "commands", "exit_status", "file_survey"}, name


def imported_modules(path: Path, package: str) -> set[str]:
    """Absolute names of every module a file imports, at any depth, except under `if TYPE_CHECKING:`."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    module = ".".join(path.relative_to(ROOT).with_suffix("").parts)
    if path.name == "__init__.py":
        module = module.removesuffix(".__init__")
        parent = module
    else:
        parent = module.rsplit(".", 1)[0]
    skipped = {id(node) for guard in ast.walk(tree) if isinstance(guard, ast.If)
               and getattr(guard.test, "id", getattr(guard.test, "attr", "")) == "TYPE_CHECKING"
               for node in ast.walk(guard)}
    names = set()
    for node in ast.walk(tree):
        if id(node) in skipped:
            continue
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = parent
            for _ in range(node.level - 1):
                base = base.rsplit(".", 1)[0]
            target = node.module if node.level == 0 else ".".join(p for p in (base, node.module) if p)
            names.add(target)
            # `from . import x` and `from .pkg import module` name modules too.
            names.update(f"{target}.{alias.name}" for alias in node.names)
    return names


def module_files(package: str) -> dict[str, Path]:
    """Module name -> file for every module of a top-level package."""
    files = {}
    for path in (ROOT / package).rglob("*.py"):
        name = ".".join(path.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")
        files[name] = path
    return files


def test_the_core_never_imports_the_ui_not_even_inside_a_function():
    offenders = {
        name: sorted(m for m in imported_modules(path, "jointid") if m.split(".")[0] in UI_PACKAGES)
        for name, path in module_files("jointid").items()
    }
    assert {name: found for name, found in offenders.items() if found} == {}


def test_the_ui_has_no_import_cycles():
    modules = module_files("tui")
    graph = {name: {m for m in imported_modules(path, "tui") if m in modules and m != name}
             for name, path in modules.items()}
    cycles = []

    def visit(node, path):
        for nxt in graph[node]:
            if nxt in path:
                cycles.append(path[path.index(nxt):] + [nxt])
            elif nxt not in done:
                visit(nxt, path + [nxt])
        done.add(node)

    done: set[str] = set()
    for start in graph:
        if start not in done:
            visit(start, [start])
    assert cycles == []


def test_the_cycle_finder_sees_a_lazy_import(tmp_path, monkeypatch):
    # The check above must see imports inside functions: app.py <-> help.py was one.
    source = "def f():\n    from .help import x\n"
    path = ROOT / "tui" / "app.py"
    monkeypatch.setattr(Path, "read_text", lambda self, encoding=None: source if self == path else "")
    assert "tui.help" in imported_modules(path, "tui")


SYNTHETIC_COMMANDS = (["fit"], ["fit", "--json"], ["sweep"], ["matrix"])
UNUSED_AT_START = {"jointid.studies.sensitivity", "jointid.present.sensitivity", "jointid.synthetic.fourier",
                   "jointid.estimation.bounded", "jointid.model.breakdown"}
"""What a synthetic, unconstrained run has no use for: these serve log fits, designed motions, the sign
constraint and `jointid torque`."""


@pytest.mark.parametrize("command", SYNTHETIC_COMMANDS, ids=" ".join)
def test_a_synthetic_command_loads_nothing_it_does_not_use(command):
    loaded = packages_loaded("jointid.cli", {"jointid"}, run=f"jointid.cli.main({command!r})")
    assert "jointid.estimation.fit" in loaded  # the command did run
    assert sorted(UNUSED_AT_START.intersection(loaded)) == []


def test_the_modules_left_out_still_load_when_needed():
    # The check above must be able to fail: a constrained fit loads jointid.estimation.bounded.
    assert "jointid.estimation.bounded" in packages_loaded(
        "jointid.cli", {"jointid"}, run="jointid.cli.main(['fit', '--constrained', '--json'])")
