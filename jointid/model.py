"""Joint models as data: an ordered list of terms, each a parameter times a regressor column.

The lesson's model, `plain`, is tau = I*qdd + h*g*cos(q) + B*qd. q is measured
counter-clockwise from world +x (q = 0 points horizontally right), gravity acts
along world -y, and positive torque drives q upward. The gravity and damping
terms are *compensation* torques: the actuator supplies them, so a horizontal
hold needs tau = h*g.

Everything downstream (fit, standard errors, verdicts, sweeps, readouts, JSON,
charts) takes the number of parameters, their names, units and sign rules from
a `JointModel`; nothing else knows that the lesson's model has three terms.
Other models are `plain` plus extra terms, named like ``coulomb+bias``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import numpy as np

G = 9.81
"""Gravitational acceleration (m/s^2)."""

POSITIVE = "positive"
"""Sign rule: the parameter must be greater than zero."""
NONNEGATIVE = "nonnegative"
"""Sign rule: the parameter must be at least zero."""


@dataclass(frozen=True)
class Term:
    """One model term: a parameter (name, label, unit, sign rule) times a regressor column.

    `column(q, qd, qdd)` maps (N,) states to the (N,) column; `invisible_when`
    says in a few words why data can leave the column zero in every sample.
    """

    name: str
    """Symbol, the key in JSON objects (e.g. 'I')."""
    label: str
    """Plain-language name (e.g. 'inertia')."""
    unit: str
    """SI unit of the parameter."""
    column: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]
    """The regressor column from (N,) arrays q, qd, qdd, e.g. qdd for the inertia."""
    sign: str | None
    """POSITIVE, NONNEGATIVE, or None for no sign rule."""
    invisible_when: str
    """Why the column can be zero in every sample, e.g. 'no acceleration'."""

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
        """True where values break the sign rule (never for a term without one); any shape."""
        values = np.asarray(values, dtype=float)
        if self.sign == POSITIVE:
            return ~(values > 0)
        if self.sign == NONNEGATIVE:
            return ~(values >= 0)
        return np.zeros(values.shape, dtype=bool)


INERTIA = Term("I", "inertia", "kg m²", lambda q, qd, qdd: qdd, POSITIVE, "no acceleration")
MASS_MOMENT = Term("h", "mass moment", "kg m", lambda q, qd, qdd: G * np.cos(q), NONNEGATIVE,
                   "no gravity torque")
DAMPING = Term("B", "damping", "N m s/rad", lambda q, qd, qdd: qd, NONNEGATIVE, "no velocity")
COULOMB = Term("Fc", "Coulomb friction", "N m", lambda q, qd, qdd: np.sign(qd), NONNEGATIVE,
               "no velocity")
BIAS = Term("tau0", "torque bias", "N m", lambda q, qd, qdd: np.ones_like(q), None,
            "no samples")


@dataclass(frozen=True)
class JointModel:
    """A joint model: its name (as the user gives it) and its terms in theta order."""

    name: str
    terms: tuple[Term, ...]

    @cached_property
    def names(self) -> tuple[str, ...]:
        """Parameter symbols in theta order."""
        return tuple(term.name for term in self.terms)

    @property
    def size(self) -> int:
        """p, the number of parameters."""
        return len(self.terms)

    def term(self, name: str) -> Term:
        """The term with symbol `name`."""
        return self.terms[self.names.index(name)]

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

    def sign_failure_mask(self, theta) -> np.ndarray:
        """(p,) or (p, K) True where a parameter breaks its term's sign rule."""
        theta = np.asarray(theta, dtype=float)
        return np.stack([term.sign_fails(value) for term, value in zip(self.terms, theta)])

    def sign_failures(self, theta) -> tuple[str, ...]:
        """Names of the parameters in theta (p,) that break their sign rules."""
        return tuple(name for name, failed in zip(self.names, self.sign_failure_mask(theta)) if failed)

    def true_values(self) -> np.ndarray:
        """(p,) The synthetic joint's value of each parameter (0 for terms it does not have)."""
        return np.array([TRUE_VALUES.get(name, 0.0) for name in self.names])


PLAIN = JointModel("plain", (INERTIA, MASS_MOMENT, DAMPING))
"""The lesson's model tau = I*qdd + h*g*cos(q) + B*qd."""

EXTRA_TERMS = {"coulomb": COULOMB, "bias": BIAS}
"""Terms that can be added to `plain`, by the name used in model names."""

TRUE_VALUES = {"I": 0.8, "h": 0.4, "B": 0.15}
"""The synthetic joint's parameters by symbol."""

TRUE_PARAMETERS = PLAIN.true_values()
"""The synthetic joint's parameters [I, h, B] in the plain model's order."""

# Kept for the library's users: the plain model's names in theta order.
PARAMETER_NAMES = PLAIN.names


class ModelError(ValueError):
    """An unknown model name; the message is one line for a user."""


def describe_models() -> str:
    """The accepted model names, as a phrase for help and error messages."""
    extras = ", ".join(EXTRA_TERMS)
    return f"plain, or plain plus any of {extras} joined with + (e.g. {'+'.join(EXTRA_TERMS)})"


def model_named(name: str) -> JointModel:
    """The model a name like 'plain', 'bias' or 'coulomb+bias' stands for; ModelError if unknown."""
    parts = [part.strip().lower() for part in str(name).split("+")]
    extras = [part for part in parts if part != "plain"]
    unknown = [part for part in extras if part not in EXTRA_TERMS]
    if not name or unknown or len(set(extras)) != len(extras) or "" in parts:
        raise ModelError(f"unknown model {name!r}: use {describe_models()}")
    ordered = [key for key in EXTRA_TERMS if key in extras]  # terms in one order whatever the spelling
    return JointModel(str(name), PLAIN.terms + tuple(EXTRA_TERMS[key] for key in ordered))


def regressor(q, qd, qdd, model: JointModel = PLAIN) -> np.ndarray:
    """(N, p) Regressor rows of `model` (default the lesson's [qdd, g*cos(q), qd])."""
    return model.regressor(q, qd, qdd)


def predict_torque(q, qd, qdd, theta=TRUE_PARAMETERS, model: JointModel = PLAIN) -> np.ndarray:
    """Actuator torque (N m) at states (q, qd, qdd) for `model`'s parameters theta."""
    return model.regressor(q, qd, qdd) @ np.asarray(theta, dtype=float)


@dataclass(frozen=True, eq=False)
class TorqueBreakdown:
    """Inverse dynamics of the plain model at given states, split into its three contributions.

    Every field has the shape of the broadcast states.
    """

    inertia: np.ndarray
    """I*qdd (N m)."""
    gravity: np.ndarray
    """h*g*cos(q), the gravity compensation (N m)."""
    damping: np.ndarray
    """B*qd, the damping compensation (N m)."""
    damper_power: np.ndarray
    """B*qd^2, mechanical power the damper dissipates (W)."""

    @property
    def total(self) -> np.ndarray:
        """Actuator torque I*qdd + h*g*cos(q) + B*qd (N m)."""
        return self.inertia + self.gravity + self.damping


def torque_breakdown(q, qd, qdd, theta=TRUE_PARAMETERS) -> TorqueBreakdown:
    """The plain model's torque contributions at states (q, qd, qdd) for theta = [I, h, B]."""
    inertia, mass_moment, damping = (float(v) for v in theta)
    q, qd, qdd = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (q, qd, qdd)))
    return TorqueBreakdown(
        inertia=inertia * qdd,
        gravity=mass_moment * G * np.cos(q),
        damping=damping * qd,
        damper_power=damping * qd**2,
    )
