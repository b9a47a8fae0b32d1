"""The simulation check: does the fitted model, driven by the true torque, follow the true motion?

Torque prediction at given states (the held-out RMSE) does not integrate
anything. Here the fitted model is run forward in time: under the true joint's
noiseless (measured) torque along the validation motion, the fitted equation
I*qdd + sum of the other terms(q, qd) = tau(t) is integrated from the true
state, restarting from the true state every `horizon` seconds so one bad
stretch does not spoil the rest. A window whose angle error exceeds
DIVERGED_ANGLE is reported as diverged rather than averaged in; the RMS angle
error covers the other windows. A negative fitted inertia turns the joint
upside down (gravity then pushes it away from the motion), which is what the
check exposes. Coulomb terms' sign(qd) is smoothed to tanh(qd/COULOMB_SMOOTHING)
in the simulation only, so the integrator can step through qd = 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..estimation.fit import FitResult
from ..model.terms import G, JointModel
from ..model.truth import TrueJoint
from ..options import DEFAULT_HORIZON, HORIZON_LIMITS
from ..synthetic.motions import DURATION, VALIDATION_MOTION, Motion

DIVERGED_ANGLE = 1.0
"""A window whose angle error exceeds this (rad) has diverged: it is counted, not averaged in."""
COULOMB_SMOOTHING = 0.01
"""Velocity scale (rad/s) of tanh(qd/scale), the simulation's stand-in for sign(qd)."""
SAMPLES_PER_SECOND = 100
"""Instants per second at which simulated and true angles are compared."""
EVALUATIONS_PER_WINDOW = 2_000
"""Work budget of one window (the fits of the ladder need at most about 1,400): a fit that needs more (an inertia held near zero makes the equation
stiff) cannot follow the motion in reasonable time, and its window counts as diverged."""


class _OverBudget(Exception):
    """The integrator used up a window's evaluations."""

SIMULATED_COLUMNS = {
    "h": lambda q, qd: G * math.cos(q),
    "h_c": lambda q, qd: G * math.cos(q),
    "h_s": lambda q, qd: G * math.sin(q),
    "B": lambda q, qd: qd,
    "Fc": lambda q, qd: math.tanh(qd / COULOMB_SMOOTHING),
    "tau0": lambda q, qd: 1.0,
}
"""Every column except the inertia's, as scalar functions of (q, qd) for the integrator."""


@dataclass(frozen=True, eq=False)
class SimulationCheck:
    """Angle errors of the fitted model integrated window by window along the validation motion."""

    horizon: float
    """Seconds between restarts from the true state."""
    window_starts: np.ndarray
    """(W,) Start time of each window (s)."""
    window_errors: tuple[np.ndarray | None, ...]
    """Per window, the (M,) angle errors (rad) at its comparison instants, or None when it diverged."""
    smoothed: bool
    """True when a Coulomb term's sign(qd) was smoothed for the integrator."""

    @property
    def diverged_windows(self) -> int:
        """How many windows diverged (angle error above DIVERGED_ANGLE, or the integration failed)."""
        return sum(errors is None for errors in self.window_errors)

    @cached_property
    def rmse(self) -> float | None:
        """RMS angle error (rad) over the windows that did not diverge, or None when all did."""
        kept = [errors for errors in self.window_errors if errors is not None]
        return None if not kept else float(np.sqrt(np.mean(np.square(np.concatenate(kept)))))


def check_horizon(horizon: float) -> None:
    """Raise ValueError unless the horizon is a finite number of seconds within HORIZON_LIMITS."""
    low, high = HORIZON_LIMITS
    if not (isinstance(horizon, (int, float)) and math.isfinite(horizon) and low <= horizon <= high):
        raise ValueError(f"horizon must be a number of seconds from {low:g} to {high:g}; got {horizon!r}")


def simulation_check(result: FitResult, joint: TrueJoint, horizon: float = DEFAULT_HORIZON,
                     motion: Motion = VALIDATION_MOTION) -> SimulationCheck | None:
    """Integrate a fit along `motion` under the joint's true torque, restarting every `horizon` s.

    None when the fit has no unique estimate (nothing to integrate).
    """
    return simulate_model(result.model, result.column_estimate, joint, horizon, motion)


def simulate_model(model: JointModel, column_estimate: np.ndarray | None, joint: TrueJoint,
                   horizon: float = DEFAULT_HORIZON, motion: Motion = VALIDATION_MOTION) -> SimulationCheck | None:
    """Integrate a model with these column coefficients (None: no unique fit, returns None); see simulation_check."""
    from scipy.integrate import solve_ivp  # lazy: only this check needs scipy

    check_horizon(horizon)
    if column_estimate is None or "I" not in model.column_names:
        return None
    theta = dict(zip(model.column_names, map(float, column_estimate)))
    inertia = theta.pop("I")
    others = [(value, SIMULATED_COLUMNS[name]) for name, value in theta.items()]

    def torque(t: float) -> float:
        states = motion.states(t)
        return float(joint.measured_torque(states.q, states.qd, states.qdd))

    evaluations = [0]

    def rates(t: float, state: np.ndarray) -> list[float]:
        evaluations[0] += 1
        if evaluations[0] > EVALUATIONS_PER_WINDOW:
            raise _OverBudget
        q, qd = state
        rest = sum(value * column(q, qd) for value, column in others)
        return [qd, (torque(t) - rest) / inertia]

    starts = np.arange(0.0, DURATION, horizon)
    errors = []
    for start in starts:
        stop = min(start + horizon, DURATION)
        instants = np.linspace(start, stop, max(2, int(round((stop - start) * SAMPLES_PER_SECOND)) + 1))
        truth = motion.states(instants)
        logged = joint.logged_angle(truth.q)
        evaluations[0] = 0
        outcome = _integrate(solve_ivp, rates, (start, stop), [float(logged[0]), float(truth.qd[0])], instants)
        if outcome is None:
            errors.append(None)
            continue
        angle_error = outcome - logged
        errors.append(angle_error if np.max(np.abs(angle_error)) <= DIVERGED_ANGLE else None)
    return SimulationCheck(horizon, starts, tuple(errors), smoothed="Fc" in theta)


def _integrate(solve_ivp, rates, span, initial, instants) -> np.ndarray | None:
    """The simulated angle at `instants`, or None when the integration fails or leaves the diverged range."""

    def escaped(t, state):  # stop early once the angle is clearly lost: the window has diverged
        return 10 * DIVERGED_ANGLE - abs(state[0] - initial[0]) if abs(state[0]) < 1e6 else -1.0

    escaped.terminal = True
    try:
        with np.errstate(all="ignore"):
            solution = solve_ivp(rates, span, initial, method="LSODA", t_eval=instants, rtol=1e-9, atol=1e-11,
                                 events=escaped)
    except _OverBudget:
        return None
    if solution.status != 0 or solution.y.shape[1] != len(instants) or not np.all(np.isfinite(solution.y[0])):
        return None
    return solution.y[0]
