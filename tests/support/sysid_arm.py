"""A simulated WPILib SysId arm routine, written as a .wpilog with robotpy-wpiutil's own writer (not jointid's code).

The arm behind the gains (volts): kA qdd = V - kS sgn(qd) - kG cos(q + offset) - kV qd, with stiction at rest
(the arm stays put while |V - kG cos(q + offset)| <= kS), integrated with scipy.integrate.solve_ivp piece by
piece between stops. Each test starts at rest hanging down (q + offset = -pi/2): quasistatic ramps of 1 V/s and
dynamic steps of 7 V, forward and reverse, as SysIdRoutine runs them. Each loop samples at jittered times (1 %
of the step), the position through a 12-bit encoder (4096 counts a turn), the velocity with Gaussian noise; the
records are written as SysIdRoutineLog writes them: voltage, position and velocity entries named
`<kind>-<motor>-<routine>` with their unit's name as metadata, then the test state.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

GAINS = {"kS": 0.2, "kG": 0.9, "kV": 1.8, "kA": 0.12, "offset": -0.05}
"""The arm's SysId gains (V, V, V s/rad, V s²/rad) and angle offset (rad)."""

RAMP = 1.0
"""Quasistatic ramp rate (V/s)."""
STEP = 7.0
"""Dynamic step (V)."""
COUNTS = 4096
"""Encoder counts per turn (12 bits)."""
VELOCITY_NOISE = 0.02
"""Standard deviation of the logged velocity's noise (rad/s)."""
JITTER = 0.01
"""Each loop's period varies uniformly within +-1 %."""

TESTS = (("quasistatic-forward", 1), ("quasistatic-reverse", -1), ("dynamic-forward", 1), ("dynamic-reverse", -1))
"""The routine's tests in the order run, with their direction."""


@dataclass(frozen=True)
class Routine:
    """How long each test runs, how often it is sampled, and the log's names."""

    quasistatic: float = 3.0
    dynamic: float = 1.2
    period: float = 0.005
    pause: float = 1.0
    """Seconds between tests (state "none", no motor records)."""
    routine: str = "arm"
    motor: str = "arm-motor"
    seed: int = 3


def voltage(test: str, direction: int, t):
    """The test's voltage at time t (s) from its start."""
    if test.startswith("quasistatic"):
        return direction * RAMP * np.asarray(t, dtype=float)
    return direction * STEP * np.ones_like(np.asarray(t, dtype=float))


def simulate_test(test: str, direction: int, times: np.ndarray, gains: dict = GAINS):
    """(q, qd) of the arm at `times` (s from the test's start, increasing), from rest hanging down."""
    kS, kG, kV, kA, offset = (gains[k] for k in ("kS", "kG", "kV", "kA", "offset"))
    net = lambda t, q: float(voltage(test, direction, t)) - kG * math.cos(q + offset)  # noqa: E731
    return stick_slip(net, kS, kV, kA, -math.pi / 2 - offset, times)


def stick_slip(net, kS: float, kV: float, kA: float, start: float, times: np.ndarray, max_step: float = np.inf,
               rtol: float = 1e-11):
    """(x, v) at `times` of kA a = net(t, x) - kS sgn(v) - kV v from rest at `start`, where the mechanism stays put
    while |net(t, x)| <= kS (stiction): solve_ivp piece by piece between stops."""
    from scipy.integrate import solve_ivp
    from scipy.optimize import brentq

    end = float(times[-1])
    t, q, qd, moving = 0.0, start, 0.0, 0
    pieces = []  # (start, stop, function of t -> (q, qd))
    while t < end:
        if moving == 0:
            begin = t
            if abs(net(t, q)) <= kS:  # stuck until the voltage overcomes gravity and stiction
                grid = np.arange(t, end + 1e-3, 1e-3)
                over = [s for s in grid if abs(net(s, q)) > kS]
                if not over:
                    pieces.append((begin, end, lambda s, q=q: (q, 0.0)))
                    break
                later = over[0]
                t = brentq(lambda s, q=q: abs(net(s, q)) - kS, max(later - 1e-3, begin), later, xtol=1e-12) + 1e-12
            pieces.append((begin, t, lambda s, q=q: (q, 0.0)))
            moving = 1 if net(t, q) > 0 else -1
            continue

        def rhs(s, y, d=moving):
            return [y[1], (net(s, y[0]) - kS * d - kV * y[1]) / kA]

        def stops(s, y, d=moving):
            return y[1]

        stops.terminal, stops.direction = True, -moving
        solution = solve_ivp(rhs, (t, end), [q, qd], method="DOP853", rtol=rtol, atol=1e-12, dense_output=True,
                             events=stops, max_step=max_step)
        stop = float(solution.t[-1])
        pieces.append((t, stop, lambda s, f=solution.sol: tuple(f(s))))
        t, (q, qd) = stop, solution.y[:, -1]
        if solution.status == 1:  # it stopped: stuck, or moving the other way at once
            qd, moving = 0.0, 0
            t += 1e-12
    q_out, qd_out = np.empty(len(times)), np.empty(len(times))
    times = np.asarray(times, dtype=float)
    done = np.zeros(len(times), dtype=bool)
    for first, last, state in pieces:  # each piece evaluated at all its times at once (its dense output)
        inside = ~done & (times >= first) & (times <= last)
        if inside.any():
            values = [np.broadcast_to(np.asarray(value, dtype=float), inside.sum())
                      for value in state(times[inside])]
            q_out[inside], qd_out[inside] = values
            done |= inside
    if not done.all():
        q_out[~done], qd_out[~done] = pieces[-1][2](pieces[-1][1])
    return q_out, qd_out


@dataclass(frozen=True)
class Samples:
    """One test's logged samples: times (s from the test's start), voltage, encoder angle (rad), velocity."""

    test: str
    t: np.ndarray
    voltage: np.ndarray
    q: np.ndarray
    qd: np.ndarray


def routine_samples(routine: Routine = Routine()) -> list[Samples]:
    """Every test of the routine, simulated and sampled with jitter, quantisation and velocity noise."""
    rng = np.random.default_rng(routine.seed)
    out = []
    for test, direction in TESTS:
        duration = routine.quasistatic if test.startswith("quasistatic") else routine.dynamic
        count = round(duration / routine.period)
        steps = routine.period * (1 + JITTER * rng.uniform(-1, 1, count - 1))
        t = np.concatenate(([0.0], np.cumsum(steps)))
        q, qd = simulate_test(test, direction, t)
        resolution = 2 * math.pi / COUNTS
        encoder = np.round(q / resolution) * resolution
        out.append(Samples(test, t, voltage(test, direction, t), encoder,
                           qd + rng.normal(0.0, VELOCITY_NOISE, len(t))))
    return out


UNIT_NAMES = {
    "rotations": ("Rotation", "Rotation per Second", 1 / (2 * math.pi)),
    "radians": ("Radian", "Radian per Second", 1.0),
}
"""Metadata of the position and velocity entries, as Java's units name them, and the values' scale from radians."""


ADVANTAGEKIT_NAMES = {"state": "/RealOutputs/SysIdTestState", "voltage": "/RealOutputs/Arm/AppliedVolts",
                      "position": "/RealOutputs/Arm/PositionRad", "velocity": "/RealOutputs/Arm/VelocityRadPerSec"}
"""Entry names as an AdvantageKit robot logs the same routine (no unit metadata)."""


def sysid_names(routine: Routine = Routine()) -> dict:
    """Entry names as SysIdRoutineLog writes them."""
    suffix = f"{routine.motor}-{routine.routine}"
    return {"state": f"sysid-test-state-{routine.routine}", "voltage": f"voltage-{suffix}",
            "position": f"position-{suffix}", "velocity": f"velocity-{suffix}"}


def write_routine_log(path: Path, samples: list[Samples], routine: Routine = Routine(), units: str = "rotations",
                      extra_entries: bool = True, names: dict | None = None, metadata: bool = True) -> Path:
    """Write the samples as SysIdRoutineLog would (plus, with `extra_entries`, a battery voltage logged alongside,
    as a robot's log has), under `names` (default sysid_names) and with the units as metadata; the path."""
    import wpiutil
    from wpiutil.log import DoubleLogEntry, StringLogEntry

    position_unit, velocity_unit, scale = UNIT_NAMES[units]
    if not metadata:
        position_unit = velocity_unit = ""
    names = names or sysid_names(routine)
    writer = wpiutil.DataLogWriter(str(path))
    start = 1_000_000  # the tests begin a second after the log does
    state = StringLogEntry(writer, names["state"], start)
    volts = DoubleLogEntry(writer, names["voltage"], "Volt" if metadata else "", start)
    position = DoubleLogEntry(writer, names["position"], position_unit, start)
    velocity = DoubleLogEntry(writer, names["velocity"], velocity_unit, start)
    battery = DoubleLogEntry(writer, "/SystemStats/BatteryVoltage", start) if extra_entries else None
    offset = start
    written = 0
    for test in samples:
        stamps = offset + np.round(test.t * 1e6).astype(np.int64)
        for k, stamp in enumerate(stamps):
            stamp = int(stamp)
            volts.append(float(test.voltage[k]), stamp)
            position.append(float(test.q[k] * scale), stamp + 15)
            velocity.append(float(test.qd[k] * scale), stamp + 30)
            state.append(test.test, stamp + 45)
            if battery is not None and k % 4 == 0:
                battery.append(12.3 - 0.05 * abs(float(test.voltage[k])), stamp + 60)
            written += 1
            if written % 500 == 0:
                writer.flush()  # robotpy-wpiutil 2026.2.2 deadlocks when its buffer fills between flushes
        offset = int(stamps[-1]) + 20_000
        state.append("none", offset)
        offset += int(routine.pause * 1e6)
    writer.flush()
    writer.stop()
    return path


if __name__ == "__main__":  # docs/examples/sysid_arm.wpilog: python tests/support/sysid_arm.py PATH
    import sys

    write_routine_log(Path(sys.argv[1]), routine_samples())
