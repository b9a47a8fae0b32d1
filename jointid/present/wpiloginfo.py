"""What `jointid log-info` prints for a WPILib data log, and the entry lines the explorer's entry picker shows."""

from __future__ import annotations

from ..text_safety import shown_name
from .text import COLUMN_GAP


def entry_line(entry) -> str:
    """"/Arm/Position: double, 1000 records at 250 Hz, Rotation" for a wpilog.Entry."""
    rate = "" if entry.rate is None else f" at {entry.rate:.4g} Hz"
    unit = "" if entry.unit is None else f", {shown_name(entry.unit)}"
    return f"{shown_name(entry.name)}: {shown_name(entry.type)}, {entry.records} records{rate}{unit}"


def _columns(header: list[str], rows: list[list[str]], right: tuple[int, ...]) -> str:
    """Rows under a header, the columns in `right` right-aligned."""
    table = [header, *rows]
    widths = [max(len(row[i]) for row in table) for i in range(len(header))]
    return "\n".join(
        COLUMN_GAP.join(cell.rjust(w) if i in right else cell.ljust(w) for i, (cell, w) in enumerate(zip(row, widths)))
        .rstrip() for row in table)


def wpilog_info_text(info) -> str:
    """The text of `jointid log-info` for a wpilog.WpilogInfo (times: seconds of the log's own time stamps)."""
    from ..logs.wpilog import fit_line

    count = len(info.entries)
    lines = [f"{shown_name(info.path)}: WPILib data log, {info.duration:.6g} s, {count} "
             f"entr{'y' if count == 1 else 'ies'}; times are seconds of its own time stamps, as --train-window and "
             "--exclude take them" + (" (negative: recorded before the log started)" if info.start_us < 0 else ""), ""]
    # Names, types and units are the log's, not the program's: escaped (a raw ESC would drive the terminal).
    rows = [[shown_name(e.name), shown_name(e.type), str(e.records), "-" if e.rate is None else f"{e.rate:.4g}",
             "-" if e.first_us is None else f"{e.first_us * 1e-6:.6g}", "-" if e.unit is None else shown_name(e.unit)]
            for e in info.entries]
    lines.append(_columns(["entry", "type", "records", "rate (Hz)", "from (s)", "unit"], rows, (2, 3, 4)))
    if not any(entry.numeric for entry in info.entries):
        lines += ["", "No numeric entry (double, float or int64): nothing jointid can fit."]
    for routine in info.lacking_voltage:
        lines += ["", (f"SysId routine {routine!r} has a test-state entry but no "
                  f"voltage-<motor>-{shown_name(routine)} entry: without the voltage there is no effort to fit.")]
    by_routine: dict = {}
    for routine in info.routines:
        by_routine.setdefault(routine.routine, []).append(routine)
    several = len(by_routine) > 1
    for name, motors in by_routine.items():
        lines.append("")
        for motor in motors:
            logged = ", ".join(shown_name(entry) for entry in (motor.position, motor.velocity) if entry)
            lines.append(f"SysId routine {name!r}, motor {motor.motor!r}: effort from {shown_name(motor.voltage)}, "
                         f"motion from {logged}" + ("" if motor.position else " (no position: q is the velocity "
                                                    "integrated)"))
        fit = fit_line(info.path, *(("--sysid-motor", name) if several else ()))
        if len(motors) > 1:
            lines.append(f"`{fit}` fits the tests of its {len(motors)} motors pooled as runs of one mechanism; "
                         f"`{fit_line(info.path, '--sysid-motor', motors[0].motor)}` fits one motor.")
        else:
            lines.append(f"`{fit}` fits its tests as runs of one joint.")
        runs = info.named_runs(name)
        lines.append(_columns(["test", "from (s)", "to (s)", "state records"],
                              [[run, f"{a * 1e-6:.6g}", f"{b * 1e-6:.6g}", str(n)]
                               for (test, a, b, n), run in runs], (1, 2, 3)) if runs else "  no test recorded")
    if not info.routines and any(entry.numeric for entry in info.entries) and not info.lacking_voltage:
        lines += ["", "Not a SysId routine log: name the joint's entries with --entry q=ENTRY,qd=ENTRY,tau=ENTRY."]
    return "\n".join(lines)
