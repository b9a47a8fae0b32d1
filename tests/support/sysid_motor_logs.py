"""SysId routine logs of a simple motor (a drive, a flywheel) in closed form, written with robotpy-wpiutil's writer.

The motor behind the gains: V = kS sgn(v) + kV v + kA a. From rest, a quasistatic ramp V = r t moves once r t
passes kS, and then, with s the time since and tau = kA / kV,
    v = (r / kV) (s - tau (1 - exp(-s / tau))),  q = (r / kV) (s^2 / 2 - tau s + tau^2 (1 - exp(-s / tau)));
a dynamic step V0 gives v = ((V0 - kS) / kV) (1 - exp(-s / tau)), q = ((V0 - kS) / kV) (s - tau (1 - exp(-s / tau))).
A reverse test is the same, negated. The logged velocity may trail the true one by a known delay (v(t - delay)),
as a SPARK MAX's does. Records are written as SysIdRoutineLog writes them (voltage, position, velocity, then the
test state, microseconds apart each loop), with other robot entries written before and around the routine.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

GAINS = {"kS": 0.15, "kV": 2.5, "kA": 0.3}
"""The motor's gains per metre (V, V s/m, V s²/m)."""

RAMP = 1.0
"""Quasistatic ramp (V/s)."""
STEP = 6.0
"""Dynamic step (V)."""
TESTS = (("quasistatic-forward", 1), ("quasistatic-reverse", -1), ("dynamic-forward", 1), ("dynamic-reverse", -1))


def motion(test: str, direction: int, s: np.ndarray, gains: dict = GAINS) -> tuple[np.ndarray, np.ndarray]:
    """(position, velocity) at `s` seconds from the test's start (negative s: at rest before it), from rest at 0."""
    kS, kV, kA = gains["kS"], gains["kV"], gains["kA"]
    tau = kA / kV
    s = np.asarray(s, dtype=float)
    if test.startswith("quasistatic"):
        moving = np.maximum(s - kS / RAMP, 0.0)
        decay = 1 - np.exp(-moving / tau)
        v = RAMP / kV * (moving - tau * decay)
        q = RAMP / kV * (moving ** 2 / 2 - tau * moving + tau ** 2 * decay)
    else:
        moving = np.maximum(s, 0.0)
        decay = 1 - np.exp(-moving / tau)
        v = (STEP - kS) / kV * decay
        q = (STEP - kS) / kV * (moving - tau * decay)
    return direction * q, direction * v


def volts(test: str, direction: int, s: np.ndarray) -> np.ndarray:
    """The test's voltage at `s` seconds from its start."""
    return direction * (RAMP * s if test.startswith("quasistatic") else STEP * np.ones_like(s))


@dataclass(frozen=True)
class MotorRoutine:
    """How the routine runs and how it is logged."""

    routine: str = "drive"
    motors: dict = field(default_factory=lambda: {"left": GAINS})
    """Motor name -> its gains."""
    quasistatic: float = 4.0
    dynamic: float = 1.5
    period: float = 0.02
    pause: float = 3.0
    start: float = 20.0
    """Seconds of the log's own clock at which the routine starts (other entries are written from 0.1 s)."""
    position_unit: str | None = "Meter"
    """The position entry's unit; None: no position entry (a velocity-only routine)."""
    velocity_unit: str = "Meter per Second"
    delay: float = 0.0
    """Seconds the logged velocity trails the true one."""
    repeat_first: float | None = None
    """Run quasistatic-forward first for this many seconds, then again in full after `gap` (no "none" between)."""
    gap: float = 23.0
    short: dict = field(default_factory=dict)
    """Test -> samples to keep (a test cut short)."""
    seed: int = 5


def write_motor_log(path: Path, routine: MotorRoutine = MotorRoutine()) -> Path:
    """Write the routine's log; the path."""
    import wpiutil
    from wpiutil.log import DoubleLogEntry, StringLogEntry

    rng = np.random.default_rng(routine.seed)
    writer = wpiutil.DataLogWriter(str(path))
    battery = DoubleLogEntry(writer, "/SystemStats/BatteryVoltage", 100_000)
    for k in range(10):  # robot code writing before the routine
        battery.append(12.4, 100_000 + 200_000 * k)
    state = StringLogEntry(writer, f"sysid-test-state-{routine.routine}", 100_000)
    entries = {}
    for motor in routine.motors:
        suffix = f"{motor}-{routine.routine}"
        entries[motor] = (
            DoubleLogEntry(writer, f"voltage-{suffix}", "Volt", 100_000),
            None if routine.position_unit is None else
            DoubleLogEntry(writer, f"position-{suffix}", routine.position_unit, 100_000),
            DoubleLogEntry(writer, f"velocity-{suffix}", routine.velocity_unit, 100_000),
        )
    plan = list(TESTS)
    if routine.repeat_first is not None:
        plan.insert(0, ("quasistatic-forward", 1))
    clock = routine.start
    written = 0
    for index, (test, direction) in enumerate(plan):
        duration = routine.quasistatic if test.startswith("quasistatic") else routine.dynamic
        if routine.repeat_first is not None and index == 0:
            duration = routine.repeat_first
        count = round(duration / routine.period)
        if test in routine.short:
            count = routine.short[test]
        steps = routine.period * (1 + 0.01 * rng.uniform(-1, 1, count - 1))
        s = np.concatenate(([0.0], np.cumsum(steps)))
        for motor, (voltage, position, velocity) in entries.items():
            gains = routine.motors[motor]
            q, _ = motion(test, direction, s, gains)
            _, lagged = motion(test, direction, s - routine.delay, gains)
            stamps = np.round((clock + s) * 1e6).astype(np.int64)
            for k, stamp in enumerate(stamps):
                voltage.append(float(volts(test, direction, s[k])), int(stamp))
                if position is not None:
                    position.append(float(q[k]), int(stamp) + 15)
                velocity.append(float(lagged[k]), int(stamp) + 30)
                written += 1
                if written % 400 == 0:
                    writer.flush()  # robotpy-wpiutil deadlocks when its buffer fills between flushes
        for stamp in np.round((clock + s) * 1e6).astype(np.int64):
            state.append(test, int(stamp) + 45)
        end = clock + s[-1]
        if routine.repeat_first is not None and index == 0:
            clock = end + routine.gap  # run again, with no "none" between
            continue
        state.append("none", int(round((end + 0.02) * 1e6)))
        battery.append(12.1, int(round((end + 0.03) * 1e6)))
        clock = end + routine.pause
    writer.flush()
    writer.stop()
    return path


def run_starts(routine: MotorRoutine = MotorRoutine()) -> list[float]:
    """Seconds of the log's clock at which each test run starts, as written."""
    rng = np.random.default_rng(routine.seed)
    plan = list(TESTS)
    if routine.repeat_first is not None:
        plan.insert(0, ("quasistatic-forward", 1))
    clock, starts = routine.start, []
    for index, (test, _) in enumerate(plan):
        duration = routine.quasistatic if test.startswith("quasistatic") else routine.dynamic
        if routine.repeat_first is not None and index == 0:
            duration = routine.repeat_first
        count = routine.short.get(test, round(duration / routine.period))
        steps = routine.period * (1 + 0.01 * rng.uniform(-1, 1, count - 1))
        starts.append(clock)
        end = clock + float(np.sum(steps))
        clock = end + (routine.gap if routine.repeat_first is not None and index == 0 else routine.pause)
    return starts


DRIVE_EXAMPLE = MotorRoutine(motors={"left": GAINS, "Moteur Droite": {"kS": 0.18, "kV": 2.55, "kA": 0.32}},
                             delay=0.12, repeat_first=1.2)
"""docs/sysid.md's drive: two motors in metres (one named with a space), a velocity 120 ms late, quasistatic-forward
run twice."""


if __name__ == "__main__":  # docs/sysid.md's sysid_drive.wpilog: python tests/support/sysid_motor_logs.py PATH
    import sys

    write_motor_log(Path(sys.argv[1]), DRIVE_EXAMPLE)
    print(f"wrote {sys.argv[1]}")
