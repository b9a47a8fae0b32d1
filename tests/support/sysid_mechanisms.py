"""Simulated WPILib SysId routines of the mechanisms teams characterise, as a roboRIO logs them: a flywheel, an
elevator, an arm and a velocity-only roller, written with robotpy-wpiutil's own writer (not jointid's code).

Each mechanism obeys its WPILib feedforward in the log's own unit (rotations or metres):

    kA a = V - kS sgn(v) - gravity(x) - kV v        gravity: 0, kG, or kG cos(x + offset)

with stiction at rest (it stays put while |V - gravity(x)| <= kS), integrated with scipy.integrate.solve_ivp
piece by piece between stops (the truth). Each routine runs as WPILib's SysIdRoutine does: quasistatic ramps of
1 V/s and dynamic steps of 7 V, forward then reverse, each test from rest (the elevator's reverse tests from the
top of its travel). The robot loop samples every 20 ms with jitter; an elevator's test ends at its soft travel
limits, as a team's routine is stopped there. Sensors: the flywheel's and the roller's NEO hall sensor (42
counts a turn) with a SPARK MAX's velocity (the position's change over 32 ms, averaged eight deep: it lags);
the elevator's fine encoder and the arm's 12-bit one with their velocity as the position's change per loop. The
records are written as SysIdRoutineLog writes them: `voltage-`, `position-` and `velocity-<motor>-<routine>`
with their unit's name as metadata ("Volt", "Rotation", "Rotation per Second", "Meter", "Meter per Second",
as WPILib's units name themselves), then `sysid-test-state-<routine>`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .sysid_arm import RAMP, STEP, TESTS, stick_slip, voltage

PERIOD = 0.020
"""The robot loop's period (s)."""
JITTER = 0.05
"""Each loop's period varies uniformly within +-5 %."""
HALL_COUNTS = 42
"""A NEO's hall sensor: counts per turn."""
SPARK_PERIOD = 0.032
"""A SPARK MAX's velocity measurement period (s)."""
SPARK_DEPTH = 8
"""Measurement periods a SPARK MAX's velocity is averaged over."""
VOLTAGE_NOISE = 0.01
"""Standard deviation (V) of the logged voltage about the voltage applied: the bus voltage's ripple in a motor
controller's report of its output."""
TRUTH_STEP = 0.001
"""Seconds between the truth's samples that the SPARK MAX's measurement reads."""


@dataclass(frozen=True)
class Mechanism:
    """One mechanism's truth (gains in its log's unit), its sensors, its routine and its log's names."""

    name: str
    gravity: str
    """'none' (flywheel, roller), 'constant' (elevator) or 'cosine' (arm)."""
    gains: dict
    """kS (V), kV (V s/unit), kA (V s²/unit), and kG (V) and offset (rad) when it has gravity."""
    unit: str
    """'rotations' or 'meters': the position's unit in the log."""
    resolution: float
    """The position encoder's step (log units)."""
    spark_velocity: bool
    """Velocity as a SPARK MAX measures it (else the position's change per loop)."""
    quasistatic: float
    dynamic: float
    travel: tuple[float, float] | None = None
    """Soft limits (log units) where a test is stopped, or None."""
    start: float = 0.0
    """The position every test starts at (the reverse tests of a mechanism with travel start at its top)."""
    position: bool = True
    """False for a velocity-only log (no position entry)."""
    motor: str = "motor"
    routine: str = "mechanism"
    seed: int = 5
    push: tuple[float, float, float] | None = None
    """(test index, start s, volts): an outside torque, in volts, pushing against the motion for 0.3 s."""
    ramp: float = 0.0
    """The motor controller's open-loop ramp (s from 0 to full output, a SPARK MAX's setOpenLoopRampRate): a
    dynamic step reaches its voltage over it, and the log holds the voltage applied."""

    def gravity_volts(self, x: float) -> float:
        """The voltage gravity takes at position x."""
        if self.gravity == "constant":
            return self.gains["kG"]
        if self.gravity == "cosine":
            angle = 2 * math.pi * x if self.unit == "rotations" else x
            return self.gains["kG"] * math.cos(angle + self.gains["offset"])
        return 0.0


FLYWHEEL = Mechanism("flywheel", "none", {"kS": 0.15, "kV": 0.12, "kA": 0.04}, "rotations", 1 / HALL_COUNTS,
                     True, quasistatic=8.0, dynamic=3.0, motor="shooter", routine="Shooter")
"""A shooter wheel on a NEO: about 90 rotations a second at 11 V, a time constant of 0.33 s."""
ELEVATOR = Mechanism("elevator", "constant", {"kS": 0.2, "kG": 0.6, "kV": 3.0, "kA": 0.6}, "meters", 1e-4, False,
                     quasistatic=6.0, dynamic=2.0, travel=(0.0, 1.2), motor="lift", routine="Elevator")
"""An elevator in metres on a fine encoder: 1.2 m of travel, a time constant of 0.2 s."""
ARM = Mechanism("arm", "cosine", {"kS": 0.2, "kG": 0.9, "kV": 1.8 * 2 * math.pi, "kA": 0.12 * 2 * math.pi,
                                  "offset": -0.05}, "rotations", 1 / 4096, False, quasistatic=3.0, dynamic=1.2,
                start=(-math.pi / 2 + 0.05) / (2 * math.pi), motor="arm-motor", routine="Arm")
"""tests/support/sysid_arm.py's arm (its gains per rotation here), logged at 50 Hz."""
ROLLER = Mechanism("roller", "none", {"kS": 0.1, "kV": 0.2, "kA": 0.02}, "rotations", 1 / HALL_COUNTS, True,
                   quasistatic=8.0, dynamic=2.0, position=False, motor="intake", routine="Intake")
"""An intake roller whose routine logs only velocity and voltage."""


def simulate(mechanism: Mechanism, test: str, direction: int, times: np.ndarray, start: float
             ) -> tuple[np.ndarray, np.ndarray]:
    """(x, v) of the mechanism at `times` (s from the test's start, increasing) from rest at `start`."""
    kS, kV, kA = (mechanism.gains[k] for k in ("kS", "kV", "kA"))
    push = _push_volts(mechanism, test)

    def net(t, x):
        return commanded(mechanism, test, direction, t) - push(t) - mechanism.gravity_volts(x)

    return stick_slip(net, kS, kV, kA, start, times, max_step=0.05, rtol=1e-10)


def commanded(mechanism: Mechanism, test: str, direction: int, t):
    """The voltage the motor applies at time t (a float, or an array) of a test: the routine's, a dynamic step
    through the ramp."""
    dynamic = test.startswith("dynamic")
    if np.ndim(t) == 0:  # the integrator's many scalar calls, without numpy's overhead
        t = float(t)
        volts = direction * (STEP if dynamic else RAMP * t)
        return volts * min(t / mechanism.ramp, 1.0) if dynamic and mechanism.ramp > 0 else volts
    volts = voltage(test, direction, t)
    if mechanism.ramp > 0 and dynamic:
        volts = volts * np.minimum(np.asarray(t, dtype=float) / mechanism.ramp, 1.0)
    return volts


def _push_volts(mechanism: Mechanism, test: str):
    """The outside torque (in volts) acting at time t of `test`: a hand against the motion for 0.3 s, or none."""
    if mechanism.push is None or TESTS[int(mechanism.push[0])][0] != test:
        return lambda t: 0.0
    _, begin, volts = mechanism.push
    return lambda t: volts if begin <= t <= begin + 0.3 else 0.0


def spark_velocity(truth_t: np.ndarray, truth_x: np.ndarray, at: np.ndarray, resolution: float) -> np.ndarray:
    """A SPARK MAX's velocity at times `at`: the encoder's change over each 32 ms period, averaged over the last
    eight periods (the truth's quantised position read on its 1 ms grid)."""
    counts = np.round(truth_x / resolution) * resolution
    period_ends = np.arange(truth_t[0] + SPARK_PERIOD, truth_t[-1] + 1e-9, SPARK_PERIOD)
    at_ends = np.interp(period_ends, truth_t, counts)
    starts = np.concatenate(([counts[0]], at_ends[:-1]))
    rates = (at_ends - starts) / SPARK_PERIOD
    averaged = np.array([rates[max(0, k - SPARK_DEPTH + 1):k + 1].mean() for k in range(len(rates))])
    index = np.searchsorted(period_ends, at, side="right") - 1
    return np.where(index >= 0, averaged[np.clip(index, 0, None)], 0.0)


@dataclass(frozen=True)
class TestSamples:
    """One test's logged samples: times (s from its start), voltage, position and velocity (log units)."""

    test: str
    t: np.ndarray
    voltage: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    truth_velocity: np.ndarray = field(repr=False, default=None)


def routine_samples(mechanism: Mechanism) -> list[TestSamples]:
    """Every test of the mechanism's routine: simulated, sampled by a jittered 50 Hz loop, quantised, its
    velocity measured as its motor controller measures it, and cut at the travel's soft limits."""
    rng = np.random.default_rng(mechanism.seed)
    out = []
    for test, direction in TESTS:
        duration = mechanism.quasistatic if test.startswith("quasistatic") else mechanism.dynamic
        count = round(duration / PERIOD)
        steps = PERIOD * (1 + JITTER * rng.uniform(-1, 1, count - 1))
        t = np.concatenate(([0.0], np.cumsum(steps)))
        start = mechanism.start
        if mechanism.travel is not None and direction < 0:
            start = mechanism.travel[1] - 0.05 * (mechanism.travel[1] - mechanism.travel[0])
        elif mechanism.travel is not None:
            start = mechanism.travel[0] + 0.05 * (mechanism.travel[1] - mechanism.travel[0])
        truth_t = np.arange(0.0, t[-1] + TRUTH_STEP, TRUTH_STEP)
        truth_x, truth_v = simulate(mechanism, test, direction, np.union1d(truth_t, t), start)
        grid = np.union1d(truth_t, t)
        x = np.interp(t, grid, truth_x)
        v_true = np.interp(t, grid, truth_v)
        if mechanism.travel is not None:  # the team's routine stops the test at the soft limits
            low, high = mechanism.travel
            inside = np.flatnonzero((x < low) | (x > high))
            if len(inside):
                t, x, v_true = t[:inside[0]], x[:inside[0]], v_true[:inside[0]]
        encoder = np.round(x / mechanism.resolution) * mechanism.resolution
        if mechanism.spark_velocity:
            velocity = spark_velocity(grid, truth_x, t, mechanism.resolution)
        else:
            velocity = np.concatenate(([0.0], np.diff(encoder) / np.diff(t)))
        logged = commanded(mechanism, test, direction, t) + rng.normal(0.0, VOLTAGE_NOISE, len(t))
        out.append(TestSamples(test, t, logged, encoder, velocity, v_true))
    return out


UNIT_NAMES = {"rotations": ("Rotation", "Rotation per Second"), "meters": ("Meter", "Meter per Second")}
"""The position and velocity entries' metadata, as WPILib's Java units name themselves."""


def write_mechanism_log(path: Path, mechanism: Mechanism, samples: list[TestSamples] | None = None) -> Path:
    """Write the mechanism's routine as SysIdRoutineLog does (with the robot's battery voltage logged alongside and
    a second before the first test); the path."""
    import wpiutil
    from wpiutil.log import DoubleLogEntry, StringLogEntry

    samples = routine_samples(mechanism) if samples is None else samples
    position_unit, velocity_unit = UNIT_NAMES[mechanism.unit]
    suffix = f"{mechanism.motor}-{mechanism.routine}"
    writer = wpiutil.DataLogWriter(str(path))
    begin = 1_000_000
    battery = DoubleLogEntry(writer, "/SystemStats/BatteryVoltage", 0)
    state = StringLogEntry(writer, f"sysid-test-state-{mechanism.routine}", begin)
    volts = DoubleLogEntry(writer, f"voltage-{suffix}", "Volt", begin)
    position = DoubleLogEntry(writer, f"position-{suffix}", position_unit, begin) if mechanism.position else None
    velocity = DoubleLogEntry(writer, f"velocity-{suffix}", velocity_unit, begin)
    for stamp in range(0, begin, 20_000):
        battery.append(12.4, stamp)
    offset, written = begin, 0
    for test in samples:
        stamps = offset + np.round(test.t * 1e6).astype(np.int64)
        for k, stamp in enumerate(stamps):
            stamp = int(stamp)
            volts.append(float(test.voltage[k]), stamp)
            if position is not None:
                position.append(float(test.position[k]), stamp + 15)
            velocity.append(float(test.velocity[k]), stamp + 30)
            state.append(test.test, stamp + 45)
            if k % 5 == 0:
                battery.append(12.3 - 0.05 * abs(float(test.voltage[k])), stamp + 60)
            written += 1
            if written % 500 == 0:
                writer.flush()  # robotpy-wpiutil's writer deadlocks when its buffer fills between flushes
        offset = int(stamps[-1]) + 20_000
        state.append("none", offset)
        offset += 2_000_000
    writer.flush()
    writer.stop()
    return path


def per_radian(mechanism: Mechanism) -> dict:
    """The truth's gains per radian (a rotations log's kV and kA over 2 pi), as jointid fits an angle."""
    scale = 2 * math.pi if mechanism.unit == "rotations" else 1.0
    return {name: value / scale if name in ("kV", "kA") else value for name, value in mechanism.gains.items()}


MECHANISMS = {mechanism.name: mechanism for mechanism in (FLYWHEEL, ELEVATOR, ARM, ROLLER)}
"""The simulated mechanisms by name."""


if __name__ == "__main__":  # docs/examples/sysid_flywheel.wpilog: python tests/support/sysid_mechanisms.py flywheel PATH
    import sys

    write_mechanism_log(Path(sys.argv[2]), MECHANISMS[sys.argv[1]])
