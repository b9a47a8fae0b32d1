"""Joint models as data: an ordered list of terms, each a parameter times a regressor column.

The lesson's model, `plain`, is tau = I*qdd + h*g*cos(q) + B*qd. q is measured
counter-clockwise from world +x (q = 0 points horizontally right), gravity acts
along world -y, and positive torque drives q toward increasing q. The gravity
and damping terms are *compensation* torques: the actuator supplies them, so a
horizontal hold needs tau = h*g.

Everything downstream (fit, standard errors, verdicts, sweeps, readouts, JSON,
charts) takes the number of parameters, their names, units and sign rules from
a `JointModel`; nothing else knows that the lesson's model has three terms.
Other models are `plain` plus extra terms, named like ``coulomb+bias``.

A model fits its *columns* (`terms`) and reports its *parameters*. They are the
same except for the angle offset: its model fits h_c*g*cos(q) + h_s*g*sin(q),
which is h*g*cos(q + q0) with h = hypot(h_c, h_s) and q0 = atan2(-h_s, h_c),
and it reports h and q0 (with standard errors by the delta method).

A model fitted to a voltage log (`JointModel.in_effort(VOLTAGE)`) has the same
terms with the effort in volts, named as WPILib's arm feedforward names them:
kA (qdd), kG (cos q), kV (qd), kS (sign qd), V0 (a voltage bias). Each keeps
the torque term it stands for as its `role`, so code that needs "the velocity
column" asks `model.index_of("B")` whatever the effort.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..checks import checked, real_array, text
from ..options import (
    EXTRA_TERM_NAMES,
    TRUE_VALUES,
    model_extras,
)
from .effort import TORQUE, Effort

G = 9.81
"""Gravitational acceleration (m/s^2)."""

POSITIVE = "positive"
"""Sign rule: the parameter must be greater than zero."""
NONNEGATIVE = "nonnegative"
"""Sign rule: the parameter must be at least zero."""


@dataclass(frozen=True)
class Parameter:
    """A parameter as reported: symbol, plain-language label, unit, sign rule and why data can hide it."""

    name: str
    """Symbol, the key in JSON objects (e.g. 'I')."""
    label: str
    """Plain-language name (e.g. 'inertia')."""
    unit: str
    """SI unit of the parameter."""
    sign: str | None
    """POSITIVE, NONNEGATIVE, or None for no sign rule."""
    invisible_when: str
    """Why data can carry no sign of it, e.g. 'no acceleration' (its column is then zero)."""

    @property
    def requirement(self) -> str | None:
        """The sign rule as text ('I > 0', 'h ≥ 0'), or None without one."""
        if self.sign is None:
            return None
        return f"{self.name} > 0" if self.sign == POSITIVE else f"{self.name} ≥ 0"

    @property
    def readout_label(self) -> str:
        """The lab's readout label, e.g. 'Fitted inertia (kg m²)'."""
        return f"Fitted {self.label} ({self.unit})"

    @property
    def symbol_with_unit(self) -> str:
        """e.g. 'I (kg m²)'."""
        return f"{self.name} ({self.unit})"

    def sign_fails(self, values) -> np.ndarray:
        """True where values break the sign rule (never for a parameter without one); any shape."""
        values = np.asarray(values, dtype=float)
        if self.sign == POSITIVE:
            return ~(values > 0)
        if self.sign == NONNEGATIVE:
            return ~(values >= 0)
        return np.zeros(values.shape, dtype=bool)


@dataclass(frozen=True)
class Term(Parameter):
    """A parameter times a regressor column: `column(q, qd, qdd)` maps (N,) states to the (N,) column."""

    column: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray] = field(repr=False)
    from_derivatives: bool = False
    """True when the column is qd or qdd itself, so it already carries the smoothing they were estimated with."""
    role: str = ""
    """The torque term this one plays the part of in a voltage model (kA plays I), '' when it is a torque term."""

    @property
    def kind(self) -> str:
        """The torque term's name this term stands for: its own name, or its role in a voltage model."""
        return self.role or self.name


def rounded_cos(q: np.ndarray) -> np.ndarray:
    """cos q, and exactly 0 where it is within the rounding of q itself: cos(fl(pi/2)) = 6e-17 is no gravity
    torque, and a column of such values would otherwise be column-scaled into a parameter the data 'determine'."""
    return _rounding_to_zero(np.cos(q), q)


def rounded_sin(q: np.ndarray) -> np.ndarray:
    """sin q, and exactly 0 where it is within the rounding of q itself (sin(fl(pi)) = 1.2e-16), as rounded_cos."""
    return _rounding_to_zero(np.sin(q), q)


def _rounding_to_zero(values: np.ndarray, q: np.ndarray) -> np.ndarray:
    """`values` (trigonometric, of q; changed in place) with 0 where |value| <= ROUNDING max(1, |q|)."""
    values = np.asarray(values, dtype=float)
    q = np.asarray(q, dtype=float)
    if values.ndim == 0 or values.size == 0:
        return np.where(np.abs(values) <= ROUNDING * np.maximum(1.0, np.abs(q)), 0.0, values)
    # Only values under the largest bound can be rounding: those few are checked against their own bound, rather
    # than building the bound for every sample (a million samples took four passes).
    largest = max(1.0, float(np.max(q)), -float(np.min(q)))
    near = np.flatnonzero(np.abs(values) <= ROUNDING * largest)
    if len(near):
        flat, angles = values.reshape(-1), np.broadcast_to(q, values.shape).reshape(-1)
        flat[near[np.abs(flat[near]) <= ROUNDING * np.maximum(1.0, np.abs(angles[near]))]] = 0.0
    return values


ROUNDING = 4 * np.finfo(float).eps
"""A trigonometric value this small times max(1, |q|) is rounding: q itself is only known to eps/2 of it."""

def gravity_cosine_column(q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """g cos q: the column of h, and of h_c in an angle-offset model (one function, so a log fit that needs both
    low-passes it once)."""
    return G * rounded_cos(q)


def cosine_column(q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """cos q: the column of a voltage model's kG, and of kG_c with an angle offset (as gravity_cosine_column)."""
    return rounded_cos(q)


INERTIA = Term("I", "inertia", "kg m²", POSITIVE, "no acceleration", lambda q, qd, qdd: qdd, True)
MASS_MOMENT = Term("h", "mass moment", "kg m", NONNEGATIVE, "no gravity torque", gravity_cosine_column)
DAMPING = Term("B", "damping", "N m s/rad", NONNEGATIVE, "no velocity", lambda q, qd, qdd: qd, True)
COULOMB = Term("Fc", "Coulomb friction", "N m", NONNEGATIVE, "no velocity", lambda q, qd, qdd: np.sign(qd))
BIAS = Term("tau0", "torque bias", "N m", None, "no samples", lambda q, qd, qdd: np.ones_like(q))
GRAVITY_COSINE = Term("h_c", "gravity cosine coefficient", "kg m", None, "no gravity torque", gravity_cosine_column)
GRAVITY_SINE = Term("h_s", "gravity sine coefficient", "kg m", None, "no angle away from horizontal",
                    lambda q, qd, qdd: G * rounded_sin(q))
ANGLE_OFFSET = Parameter("q0", "angle offset", "rad", None, "no angle away from horizontal")
CONSTANT_GRAVITY = Term("tauG", "gravity torque", "N m", None, "no samples", lambda q, qd, qdd: np.ones_like(q))
"""An elevator's gravity: a torque (or force) that is the same at every position, m g r at a drum of radius r."""
QUADRATIC_DRAG = Term("Bq", "quadratic drag", "N m s²/rad²", None, "no velocity", lambda q, qd, qdd: qd * np.abs(qd))
"""Not in any model: a candidate the omitted-terms test tries on a log fit's residuals (drag growing with speed)."""

# The same terms with the effort in volts, named as WPILib's ArmFeedforward names them. The gravity gain's column
# is cos q itself (kG is the voltage that holds the arm horizontal), not g cos q.
ACCELERATION_GAIN = Term("kA", "acceleration gain", "V s²/rad", POSITIVE, "no acceleration",
                         lambda q, qd, qdd: qdd, True, "I")
GRAVITY_GAIN = Term("kG", "gravity gain", "V", NONNEGATIVE, "no gravity torque", cosine_column, role="h")
VELOCITY_GAIN = Term("kV", "velocity gain", "V s/rad", NONNEGATIVE, "no velocity", lambda q, qd, qdd: qd, True, "B")
STATIC_GAIN = Term("kS", "static gain", "V", NONNEGATIVE, "no velocity", lambda q, qd, qdd: np.sign(qd),
                   role="Fc")
LOAD_GRAVITY_GAIN = Term("kG", "gravity gain", "V", None, "no samples", lambda q, qd, qdd: np.ones_like(q),
                         role="tauG")
"""ElevatorFeedforward's kG: the voltage that holds the load still, the same at every position."""
VOLTAGE_BIAS = Term("V0", "voltage bias", "V", None, "no samples", lambda q, qd, qdd: np.ones_like(q), role="tau0")
GRAVITY_COSINE_GAIN = Term("kG_c", "gravity cosine gain", "V", None, "no gravity torque", cosine_column,
                           role="h_c")
GRAVITY_SINE_GAIN = Term("kG_s", "gravity sine gain", "V", None, "no angle away from horizontal",
                         lambda q, qd, qdd: rounded_sin(q), role="h_s")
QUADRATIC_DRAG_GAIN = Term("kVq", "quadratic drag gain", "V s²/rad²", None, "no velocity",
                           lambda q, qd, qdd: qd * np.abs(qd), role="Bq")

VOLTAGE_TERMS = {term.role: term for term in (ACCELERATION_GAIN, GRAVITY_GAIN, VELOCITY_GAIN, STATIC_GAIN,
                                              VOLTAGE_BIAS, GRAVITY_COSINE_GAIN, GRAVITY_SINE_GAIN,
                                              QUADRATIC_DRAG_GAIN, LOAD_GRAVITY_GAIN)}
"""Each torque term's twin with the effort in volts, by the torque term's name."""


def in_effort(terms, effort: Effort) -> tuple[Term, ...]:
    """The terms as fitted to an effort in `effort`'s unit: themselves for torque, their volt twins for voltage."""
    return tuple(terms) if effort.is_torque else tuple(VOLTAGE_TERMS[term.kind] for term in terms)


@dataclass(frozen=True)
class AngleOffset:
    """Report the columns h_c*g*cos(q) + h_s*g*sin(q) as h = hypot(h_c, h_s) and q0 = atan2(-h_s, h_c)."""

    cosine: int
    """Index of the h_c column (where h is reported)."""
    sine: int
    """Index of the h_s column (where q0 is reported)."""

    def report(self, theta: np.ndarray) -> np.ndarray:
        """(p,) or (p, K) column coefficients -> the same shape with h and q0 in place of h_c and h_s."""
        reported = np.array(theta, dtype=float)
        h_c, h_s = theta[self.cosine], theta[self.sine]
        reported[self.cosine] = np.hypot(h_c, h_s)
        reported[self.sine] = np.arctan2(-h_s, h_c)
        return reported

    def jacobian(self, theta: np.ndarray) -> np.ndarray:
        """(p, p) d(reported)/d(columns) at theta (p,), for delta-method standard errors."""
        jacobian = np.eye(len(theta))
        h_c, h_s = float(theta[self.cosine]), float(theta[self.sine])
        h = math.hypot(h_c, h_s)  # h_c**2 would overflow beyond 1e154 (and underflow below 1e-162)
        c, s = self.cosine, self.sine
        if h == 0.0:  # both columns clamped at 0 (a test with no gravity signal): no slope exists at the origin,
            return jacobian  # so the columns' own errors stand in (q0 has no direction to be determined anyway)
        jacobian[c, c], jacobian[c, s] = h_c / h, h_s / h
        jacobian[s, c], jacobian[s, s] = h_s / h / h, -h_c / h / h
        return jacobian


@dataclass(frozen=True)
class JointModel:
    """A joint model: its name (as the user gives it), its regressor terms, and how it reports them."""

    name: str
    terms: tuple[Term, ...]
    angle_offset: AngleOffset | None = None
    """Set when the model reports h and q0 in place of its h_c and h_s columns."""
    effort: Effort = TORQUE
    """What the fitted effort is: torque (N m), or voltage (V) for the same terms named as WPILib's gains."""

    def in_effort(self, effort: Effort) -> JointModel:
        """The same model fitted to an effort in `effort`'s unit (itself when it already is)."""
        if effort == self.effort:
            return self
        torque_terms = tuple(TORQUE_TERMS[term.kind] for term in self.terms)
        return JointModel(self.name, in_effort(torque_terms, effort), self.angle_offset, effort)

    def index_of(self, kind: str) -> int | None:
        """The column index of the term standing for torque term `kind` ('I', 'B', 'Fc', 'tau0'...), or None."""
        kinds = tuple(term.kind for term in self.terms)
        return kinds.index(kind) if kind in kinds else None

    @cached_property
    def parameters(self) -> tuple[Parameter, ...]:
        """The reported parameters in theta order (the terms, with h and q0 for an angle offset)."""
        reported = list(self.terms)
        if self.angle_offset is not None:
            reported[self.angle_offset.cosine] = MASS_MOMENT if self.effort.is_torque else GRAVITY_GAIN
            reported[self.angle_offset.sine] = ANGLE_OFFSET
        return tuple(reported)

    @cached_property
    def names(self) -> tuple[str, ...]:
        """Reported parameter symbols in theta order."""
        return tuple(parameter.name for parameter in self.parameters)

    @cached_property
    def column_names(self) -> tuple[str, ...]:
        """Regressor column symbols in theta order (the same as `names` unless there is an angle offset)."""
        return tuple(term.name for term in self.terms)

    @property
    def size(self) -> int:
        """p, the number of parameters."""
        return len(self.terms)

    def parameter(self, name: str) -> Parameter:
        """The reported parameter with symbol `name`."""
        return self.parameters[self.names.index(name)]

    def term(self, name: str) -> Term:
        """The regressor term with symbol `name`."""
        return self.terms[self.column_names.index(name)]

    def columns_behind(self, name: str) -> tuple[str, ...]:
        """The column symbols a reported parameter is computed from (h and q0 come from h_c and h_s)."""
        offset = self.angle_offset
        if offset is not None and name in (self.names[offset.cosine], self.names[offset.sine]):
            return (self.column_names[offset.cosine], self.column_names[offset.sine])
        return (self.column_names[self.names.index(name)],)

    def regressor(self, q, qd, qdd) -> np.ndarray:
        """(N, p) Regressor rows, one column per term, for states of shape (N,)."""
        q, qd, qdd = (a.ravel() for a in np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (q, qd, qdd))))
        # Column-major: each column is written contiguously, and the solver's
        # column-major working copy is then a straight scaled copy.
        rows = np.empty((q.size, self.size), order="F")
        for j, term in enumerate(self.terms):
            rows[:, j] = term.column(q, qd, qdd)
        return rows

    def data_regressor(self, data) -> np.ndarray:
        """(N, p) The regressor of a JointData's states."""
        return self.regressor(data.q, data.qd, data.qdd)

    def report(self, theta: np.ndarray) -> np.ndarray:
        """(p,) or (p, K) column coefficients -> the reported parameters (the same values without an angle offset)."""
        return theta if self.angle_offset is None else self.angle_offset.report(theta)

    def report_jacobian(self, theta: np.ndarray) -> np.ndarray | None:
        """(p, p) d(reported)/d(columns) at theta (p,), or None when the parameters are the columns."""
        return None if self.angle_offset is None else self.angle_offset.jacobian(theta)

    def sign_failure_mask(self, reported) -> np.ndarray:
        """(p,) or (p, K) True where a reported parameter breaks its sign rule."""
        reported = np.asarray(reported, dtype=float)
        return np.stack([parameter.sign_fails(value) for parameter, value in zip(self.parameters, reported)])

    def sign_failures(self, reported) -> tuple[str, ...]:
        """Names of the reported parameters (p,) that break their sign rules."""
        return tuple(name for name, failed in zip(self.names, self.sign_failure_mask(reported)) if failed)


PLAIN = JointModel("plain", (INERTIA, MASS_MOMENT, DAMPING))
"""The lesson's model tau = I*qdd + h*g*cos(q) + B*qd."""

EXTRA_TERMS = dict(zip(EXTRA_TERM_NAMES, (COULOMB, BIAS, GRAVITY_SINE)))
"""Terms that can be added to `plain`, by the name used in model names, in column order."""

TORQUE_TERMS = {term.name: term for term in (INERTIA, MASS_MOMENT, DAMPING, COULOMB, BIAS, GRAVITY_COSINE,
                                             GRAVITY_SINE, QUADRATIC_DRAG, CONSTANT_GRAVITY)}
"""The torque terms by name (what a volt twin's role names)."""

CANDIDATE_TERMS = (COULOMB, BIAS, GRAVITY_SINE, QUADRATIC_DRAG)
"""Terms a log fit's residuals are tested against when its model lacks them (the ladder's, and quadratic drag)."""

SIMPLE_MOTOR = JointModel("simple", (INERTIA, DAMPING, COULOMB))
"""A flywheel, roller or drive: a joint whose gravity term is zero (WPILib's SimpleMotorFeedforward in volts)."""
ELEVATOR = JointModel("elevator", (INERTIA, CONSTANT_GRAVITY, DAMPING, COULOMB))
"""An elevator: a joint whose gravity torque is the same at every position (WPILib's ElevatorFeedforward)."""
MECHANISM_MODELS = {model.name: model for model in (SIMPLE_MOTOR, ELEVATOR)}
"""The models named by a mechanism rather than by terms added to plain (the arm's is coulomb+angle-offset)."""

TRUE_PARAMETERS = np.array([TRUE_VALUES[name] for name in PLAIN.names])
"""The lesson's joint's parameters [I, h, B] in the plain model's order."""

# Kept for the library's users: the plain model's names in theta order.
PARAMETER_NAMES = PLAIN.names


@checked(name=text)
def model_named(name: str) -> JointModel:
    """The model a name like 'plain', 'bias' or 'coulomb+angle-offset' stands for.

    Parameters
    ----------
    name : str
        'plain' or plain plus any of coulomb, bias, angle-offset joined with '+'; or a mechanism's own model:
        'simple' (I, B, Fc: no gravity term) or 'elevator' (I, a constant gravity term tauG, B, Fc).

    Returns
    -------
    JointModel
        Its terms in one column order whatever the spelling.

    Raises
    ------
    ModelError
        An unknown name (a ValueError whose message lists the choices).

    Examples
    --------
    >>> model_named("bias+coulomb").names
    ('I', 'h', 'B', 'Fc', 'tau0')
    """
    if str(name).strip().lower() in MECHANISM_MODELS:
        return MECHANISM_MODELS[str(name).strip().lower()]
    ordered = model_extras(name)
    terms = PLAIN.terms + tuple(EXTRA_TERMS[key] for key in ordered)
    if "angle-offset" not in ordered:
        return JointModel(str(name), terms)
    cosine = PLAIN.names.index("h")
    terms = terms[:cosine] + (GRAVITY_COSINE,) + terms[cosine + 1:]
    return JointModel(str(name), terms, AngleOffset(cosine=cosine, sine=len(terms) - 1))


def model_argument(value, where: str) -> JointModel:
    """The checks' rule for a model argument: a JointModel, or a model's name (as Settings and fit_log take)."""
    if isinstance(value, JointModel):
        return value
    if isinstance(value, str):
        try:
            return model_named(value)
        except ValueError as error:
            raise ValueError(f"{where}: {error}") from None
    raise TypeError(f"{where} must be a model name or a JointModel; got {type(value).__name__}")


@checked(q=real_array(), qd=real_array(), qdd=real_array(), model=model_argument)
def regressor(q, qd, qdd, model: JointModel = PLAIN) -> np.ndarray:
    """Regressor rows of `model` at the states (default the lesson's [qdd, g*cos(q), qd]).

    Parameters
    ----------
    q, qd, qdd : array_like
        (N,) angle (rad), velocity (rad/s) and acceleration (rad/s^2).
    model : JointModel
        The model whose terms give the columns.

    Returns
    -------
    numpy.ndarray
        (N, p), one column per term.

    Examples
    --------
    >>> regressor([0.0], [-3.0], [2.0]).tolist()
    [[2.0, 9.81, -3.0]]
    """
    return model.regressor(q, qd, qdd)


@checked(q=real_array(), qd=real_array(), qdd=real_array(), theta=real_array(1), model=model_argument)
def predict_torque(q, qd, qdd, theta=TRUE_PARAMETERS, model: JointModel = PLAIN) -> np.ndarray:
    """Actuator torque (N m) at the states: inverse dynamics.

    Parameters
    ----------
    q, qd, qdd : array_like
        (N,) angle (rad), velocity (rad/s) and acceleration (rad/s^2).
    theta : array_like
        (p,) coefficients of `model`'s columns (default the lesson's I = 0.8, h = 0.4, B = 0.15).
    model : JointModel
        The model.

    Returns
    -------
    numpy.ndarray
        (N,) torque.

    Examples
    --------
    >>> predict_torque([np.pi / 3], [-2.0], [3.0]).round(6).tolist()  # the lesson's exercise 2
    [4.062]
    """
    return model.regressor(q, qd, qdd) @ np.asarray(theta, dtype=float)

