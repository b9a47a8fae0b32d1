"""The start-up budget: what each start-up trick buys on its path, measured by undoing it alone.

Run from the repository root: PYTHONPATH=. .venv/bin/python benchmarks/bench_startup_budget.py [ROUNDS] [NAME ...]

Every trick runs its path as fresh processes, as shipped and with that one
trick undone (a monkeypatch or an import made before the path starts, the code
a stock Python program would run instead): each round launches the two side by
side, alternating, BEST_OF times each, and keeps each one's fastest launch
(other work on a shared machine only ever slows a launch down); the tricks'
order rotates from round to round. The paths are `jointid fit --motion rich`
(the console script, tui.command), `jointid fit --csv` of a 1e6-row log like for like (bench_log_path's; the
log is written to the temporary folder once), `jointid --help`, `jointid sweep`, and the
`jointid` command to the explorer's first complete frame at 120x40 and the
process's end (bench_tui_startup's COMMAND). What a trick buys is
1 - with / without per round: the share of its path's time (without the trick)
it saves; printed as min / median / max over the rounds, wall and CPU. The
budget's rule: a trick whose median buys less than 0.05 goes
(benchmarks/README.md, "Start-up budget", lists those removed). Tricks that
speed key presses rather than start-up are timed by bench_tui_keys.py
(`--gc both`, `--adapter KEY`). NAME arguments run only those tricks. Bytecode
caching is allowed, as on a user's machine.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from common import ENVIRONMENT, write_log  # noqa: E402  (this folder is first on sys.path)

ROUNDS = 9
BEST_OF = 3
THRESHOLD = 0.05


def command(argv: list[str], undo: str = "") -> str:
    """The console script pip installs (tui.command) run with `argv`, after the code `undo`."""
    return f"import sys\nsys.argv = ['jointid', *{argv!r}]\n{undo}\nfrom tui.command import console_script\nconsole_script()\n"


def explorer(undo: str = "", module: str = "tui.command") -> str:
    """`jointid` with no subcommand to the explorer's first complete frame, then the process's end, after `undo`."""
    from bench_tui_startup import command_line  # one template for both scripts

    return command_line(module, undo)


FIT = ["fit", "--motion", "rich"]
FIT_PATH = "`jointid fit --motion rich`"
LOG = Path(tempfile.gettempdir()) / "jointid-budget-log.csv"
"""A 1,000,000-row log of t, q, qd, qdd, tau (common.write_log), written when a trick on its path runs."""
LOG_FIT = ["fit", "--csv", str(LOG), "--json", "--model", "plain", "--no-robust", "--cutoff", "0"]
LOG_PATH = "`jointid fit --csv` 1e6 rows"
EXPLORER_PATH = "`jointid` to the first frame"

TRICKS = {
    # name: (where, path, code as shipped, code with the trick undone)
    "end-process": ("jointid/cli/output.py end_process", FIT_PATH, command(FIT),
                    command(FIT, "import jointid.cli\njointid.cli.end_process = lambda status: None")),
    # Its path is the log path like for like (bench_log_path.py), where pandas' import is most of what it saves.
    "gc-off-until-lasting": ("jointid/cli/__init__.py console_script", LOG_PATH, command(LOG_FIT),
                             command(LOG_FIT, "import gc\ngc.disable = lambda: None")),
    "metadata-on-version": ("jointid/cli/version.py", FIT_PATH, command(FIT), command(FIT, "import importlib.metadata")),
    "student-t-quantile": ("jointid/estimation/student_t.py (no scipy.special)", FIT_PATH, command(FIT),
                           command(FIT, "import scipy.special")),
    "pandas-on-first-use": ("jointid/logs/csv_reader.py", FIT_PATH, command(FIT), command(FIT, "import pandas")),
    "lazy-core-modules": (
        "every jointid module imported where first used", FIT_PATH, command(FIT),
        command(FIT, "import importlib, pkgutil, jointid\n"
                     "for info in pkgutil.walk_packages(jointid.__path__, 'jointid.'):\n"
                     "    if info.name not in ('jointid.logs.bag', 'jointid.__main__'):\n"
                     "        importlib.import_module(info.name)")),
    "lazy-package-names": ("jointid/__init__.py (PEP 562)", "`jointid --help`", command(["--help"]),
                           command(["--help"], "import jointid\nfor name in jointid.__all__:\n    getattr(jointid, name)")),
    "sweep-no-percentile": ("jointid/studies/sweep.py (no numpy.ma)", "`jointid sweep`", command(["sweep"]),
                            command(["sweep"], "import numpy.ma")),
    # Both keep importlib.metadata out of the explorer's start (tests/tui/test_startup.py), so they go or stay
    # together: the pair is what decides; each alone is printed beside it.
    "metadata-off-explorer-start": (
        "tui/command.py and adapter.installed_version together", EXPLORER_PATH, explorer(),
        explorer("from tui.third_party import adapter\nadapter._version_beside_package = lambda name: None",
                 module="jointid.cli")),
    "entry-point-hand-over": ("tui/command.py", EXPLORER_PATH, explorer(), explorer(module="jointid.cli")),
    "versions-from-dist-info": (
        "tui/third_party/adapter.py installed_version", EXPLORER_PATH, explorer(),
        explorer("from tui.third_party import adapter\nadapter._version_beside_package = lambda name: None")),
    "gc-frozen-at-first-frame": (
        "tui/app.py JointIdApp.on_ready (gc.freeze)", EXPLORER_PATH, explorer(),
        explorer("import gc\ngc.freeze = lambda: None")),
    "no-gc-restore-at-exit": (
        "tui/app.py restore_gc, tui/entry.py", EXPLORER_PATH, explorer(),
        explorer("from tui.app import JointIdApp\nunmount = JointIdApp.on_unmount\n"
                 "def on_unmount(self):\n    self.restore_gc = True\n    unmount(self)\nJointIdApp.on_unmount = on_unmount")),
    "lazy-ui-modules": (
        "tui's screens and jointid's log reader imported when first used", EXPLORER_PATH, explorer(),
        explorer("import importlib, pkgutil, tui\n"
                 "for info in pkgutil.walk_packages(tui.__path__, 'tui.'):\n"
                 "    importlib.import_module(info.name)\n"
                 "import jointid.studies.log_fit, jointid.present.documents")),
    # The adapters speed key presses, the path that decides them (bench_tui_keys.py --adapter KEY); this is their
    # share of the start, for information.
    "adapters-at-start": (
        "tui/third_party/adapter.py (all four)", EXPLORER_PATH, explorer(),
        explorer("from tui.third_party import adapter\ncheck = adapter.check\n"
                 "def no_adapters():\n    usable, lines = check()\n    return dict.fromkeys(usable, False), lines\n"
                 "adapter.check = no_adapters")),
}


def launch(code: str) -> tuple[float, float]:
    """(wall, CPU) seconds of a fresh interpreter running `code` to its exit (status 0 required)."""
    start = time.perf_counter()
    process = subprocess.Popen([sys.executable, "-c", code], cwd=ROOT, env=ENVIRONMENT, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"a run exited with {os.waitstatus_to_exitcode(status)}:\n{code}")
    return wall, usage.ru_utime + usage.ru_stime


def main() -> int:
    arguments = sys.argv[1:]
    rounds = int(arguments.pop(0)) if arguments and arguments[0].isdigit() else ROUNDS
    names = arguments or list(TRICKS)
    unknown = set(names) - set(TRICKS)
    if unknown:
        raise SystemExit(f"unknown tricks: {', '.join(sorted(unknown))}; known: {', '.join(TRICKS)}")
    if any(TRICKS[name][1] == LOG_PATH for name in names) and not LOG.exists():
        write_log(LOG, 1_000_000)
    for name in names:  # warm-up: the file cache and compiled modules, and every variant runs
        launch(TRICKS[name][2])
        launch(TRICKS[name][3])
    saved: dict[str, list[tuple[float, float]]] = {name: [] for name in names}
    scale: dict[str, list[float]] = {name: [] for name in names}
    for index in range(rounds):
        for name in names[index % len(names):] + names[:index % len(names)]:
            _, _, shipped, undone = TRICKS[name]
            runs: dict[str, list[tuple[float, float]]] = {shipped: [], undone: []}
            for repeat in range(BEST_OF):
                for code in (shipped, undone) if (index + repeat) % 2 == 0 else (undone, shipped):
                    runs[code].append(launch(code))
            with_trick, without = (min(runs[code]) for code in (shipped, undone))  # the fastest by wall time
            saved[name].append(tuple(1 - a / b for a, b in zip(with_trick, without)))
            scale[name].append(without[0])
    print(f"what each trick buys: 1 - with / without, {rounds} interleaved rounds of fresh processes (best of "
          f"{BEST_OF} each); "
          f"keep at >= {THRESHOLD:.2f} (median, wall)")
    print(f"{'trick':<27}{'path':<32}{'wall min / median / max':<26}{'CPU median':<12}verdict   (path without it, ms)")
    for name in names:
        wall = [w for w, _ in saved[name]]
        cpu = [c for _, c in saved[name]]
        middle = statistics.median(wall)
        verdict = "keep" if middle >= THRESHOLD else "remove"
        print(f"{name:<27}{TRICKS[name][1]:<32}{min(wall):+.3f} / {middle:+.3f} / {max(wall):+.3f}   "
              f"{statistics.median(cpu):+.3f}      {verdict:<9} {statistics.median(scale[name]) * 1000:.0f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
