"""`jointid report` of a large log against `jointid fit --json` of the same log.

Run from the repository root: PYTHONPATH=. .venv/bin/python benchmarks/bench_report.py [ROUNDS [ROWS]]

It writes a 1,000,000-row log of t, q, qd, qdd, tau (the rich motion at 1 kHz,
as bench_log_load's) to a temporary directory, then runs interleaved rounds of
two fresh processes, in alternating order: `jointid fit --csv FILE --json`
(what a user runs to get the numbers) and `jointid report --csv FILE --out
REPORT.html --force` (the same fit, written as a page with its charts; needs
`jointid[report]`). Both are the console script next to this interpreter, with
every import. It prints min / median / max of the per-round ratio of wall
times (goal: median <= 1.5), then, from one report, its size, how many points
each chart draws (thinned to report_charts.MAX_POINTS), and the split of the
report's own extra time (importing matplotlib, drawing, writing) measured in
this process. Exits 1 if the goal is missed.
"""

from __future__ import annotations

import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from common import write_log  # this folder is first on sys.path

ROUNDS = 9
ROWS = 1_000_000
GOAL = 1.5

ENVIRONMENT = {name: value for name, value in os.environ.items() if name != "PYTHONDONTWRITEBYTECODE"}
ENVIRONMENT["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH")) if p)
SCRIPT = Path(sys.executable).parent / "jointid"
JOINTID = [sys.executable, str(SCRIPT)] if SCRIPT.exists() else [sys.executable, "-m", "jointid"]


def wall(command: list[str]) -> float:
    """Wall seconds of one fresh process run to its end (status 0 required)."""
    start = time.perf_counter()
    done = subprocess.run(command, cwd=ROOT, env=ENVIRONMENT, stdout=subprocess.DEVNULL, check=False)
    seconds = time.perf_counter() - start
    if done.returncode:
        raise SystemExit(f"{command} exited with {done.returncode}")
    return seconds


def split_in_process(log: Path) -> dict[str, float]:
    """Seconds of the fit, matplotlib's import, drawing the report and writing its HTML, in this process."""
    from jointid.cli import build_parser
    from jointid.cli.log_arguments import fit_loaded_logs

    args = build_parser().parse_args(["report", "--csv", str(log), "--out", "unused.html"])
    times = {}
    start = time.perf_counter()
    logs = fit_loaded_logs(args)
    times["fit"] = time.perf_counter() - start
    start = time.perf_counter()
    from jointid.present import report_charts

    report_charts._matplotlib()
    times["import matplotlib"] = time.perf_counter() - start
    start = time.perf_counter()
    from jointid.present.report import logs_report

    report = logs_report(logs)
    times["build the report (charts drawn)"] = time.perf_counter() - start
    start = time.perf_counter()
    from jointid.present.report_writers import html_page

    html_page(report, "")
    times["HTML"] = time.perf_counter() - start
    return times


def main() -> int:
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else ROUNDS
    rows = int(sys.argv[2]) if len(sys.argv) > 2 else ROWS
    with tempfile.TemporaryDirectory() as folder:
        log, page = Path(folder) / "log.csv", Path(folder) / "report.html"
        write_log(log, rows)
        fit = [*JOINTID, "fit", "--csv", str(log), "--json"]
        report = [*JOINTID, "report", "--csv", str(log), "--out", str(page), "--force"]
        wall(fit), wall(report)  # warm the file cache and the bytecode
        ratios = []
        for number in range(rounds):
            if number % 2:
                seconds_report = wall(report)
                seconds_fit = wall(fit)
            else:
                seconds_fit = wall(fit)
                seconds_report = wall(report)
            ratios.append(seconds_report / seconds_fit)
            print(f"round {number + 1}: fit --json {seconds_fit:.2f} s, report {seconds_report:.2f} s, "
                  f"ratio {ratios[-1]:.2f}", flush=True)
        text = page.read_text(encoding="utf-8")
        median = statistics.median(ratios)
        print(f"\n{rows:,}-row log, {rounds} interleaved rounds")
        print(f"jointid report / jointid fit --json (wall time): min {min(ratios):.2f}, median {median:.2f}, "
              f"max {max(ratios):.2f}; goal <= {GOAL} {'met' if median <= GOAL else 'MISSED'}")
        drawn = [path.count("L ") for path in re.findall(r'<path d="([^"]{20000,})"', text)]
        print(f"report: {len(text) / 1e6:.2f} MB of HTML; points per long path (dots and lines): {drawn}")
        for name, seconds in split_in_process(log).items():
            print(f"  {name}: {seconds:.3f} s")
    return 0 if median <= GOAL else 1


if __name__ == "__main__":
    sys.exit(main())
