"""Finite Fourier series motions (Swevers et al.'s periodic excitation) and their motion files.

Over a period T with w = 2 pi / T and K harmonics,

    q(t)   = q_c + sum_k [a_k/(k w) sin(k w t) - b_k/(k w) cos(k w t)]
    qd(t)  =       sum_k [a_k cos(k w t) + b_k sin(k w t)]
    qdd(t) =       sum_k [-a_k k w sin(k w t) + b_k k w cos(k w t)]

so a_k and b_k are velocity amplitudes (rad/s), every sample is a realisable
kinematic state, and q, qd and qdd are linear in the coefficients (which is
what makes the designer's kinematic limits linear constraints).

A motion file is one JSON object: kind, period, q_c, a, b and `made`, the
record of how it was designed (criterion, limits, samples, noise, model, seed,
jointid version). Loading is strict: anything missing, extra, of the wrong type
or not finite is a MotionFileError whose message is one line naming the problem.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ..options import HARMONIC_LIMITS, PERIOD_LIMITS
from .motions import JointStates

KIND = "fourier"
"""The `kind` of a motion file jointid writes and reads."""
COEFFICIENT_LIMIT = 1000.0
"""Largest |q_c|, |a_k|, |b_k| a motion file may hold (rad, rad/s): beyond it nothing is a joint's motion."""
FILE_KEYS = ("kind", "period", "q_c", "a", "b", "made")
"""The keys of a motion file's object, in the order jointid writes them."""
FILE_SIZE_LIMIT = 1_000_000
"""Largest motion file (bytes) jointid reads: a real one is under 2 kB."""


class MotionFileError(ValueError):
    """A motion file that cannot be read or is not a valid motion; the message is one line for a user."""


@dataclass(frozen=True)
class FourierMotion:
    """A periodic motion q(t) from a finite Fourier series; usable wherever a training motion is."""

    period: float
    """T (s)."""
    q_c: float
    """The mean angle (rad)."""
    a: tuple[float, ...]
    """(K,) Cosine velocity amplitudes a_k (rad/s)."""
    b: tuple[float, ...]
    """(K,) Sine velocity amplitudes b_k (rad/s)."""
    made: Mapping = field(default_factory=dict, compare=False, hash=False)
    """How the motion was made (criterion, limits, samples, ...); not part of its identity."""
    name: str = "design"
    label: str = "Designed motion"

    @property
    def harmonics(self) -> int:
        """K, the number of harmonics."""
        return len(self.a)

    @property
    def coefficients(self) -> np.ndarray:
        """(2K+1,) [q_c, a_1..a_K, b_1..b_K], the designer's variables."""
        return np.array([self.q_c, *self.a, *self.b])

    def states(self, t) -> JointStates:
        """Evaluate q, qd, qdd analytically at times t (s), shape (N,)."""
        t = np.asarray(t, dtype=float)
        basis = fourier_basis(t, self.period, self.harmonics)
        x = self.coefficients
        return JointStates(t=t, q=basis[0] @ x, qd=basis[1] @ x, qdd=basis[2] @ x)


def fourier_basis(t, period: float, harmonics: int) -> np.ndarray:
    """(3, N, 2K+1) Matrices mapping [q_c, a, b] to q, qd and qdd at times t (N,)."""
    t = np.asarray(t, dtype=float).ravel()
    w = 2.0 * math.pi / period
    k = np.arange(1, harmonics + 1, dtype=float)
    angle = np.outer(t, k * w)  # (N, K)
    sin, cos = np.sin(angle), np.cos(angle)
    kw = k * w
    basis = np.zeros((3, t.size, 2 * harmonics + 1))
    basis[0, :, 0] = 1.0
    basis[0, :, 1:harmonics + 1] = sin / kw
    basis[0, :, harmonics + 1:] = -cos / kw
    basis[1, :, 1:harmonics + 1] = cos
    basis[1, :, harmonics + 1:] = sin
    basis[2, :, 1:harmonics + 1] = -sin * kw
    basis[2, :, harmonics + 1:] = cos * kw
    return basis


def from_coefficients(x, period: float, made: Mapping | None = None) -> FourierMotion:
    """The motion of designer variables x = [q_c, a_1..a_K, b_1..b_K] (2K+1,)."""
    x = [float(value) for value in np.asarray(x, dtype=float)]
    harmonics = (len(x) - 1) // 2
    return FourierMotion(period=float(period), q_c=x[0], a=tuple(x[1:harmonics + 1]),
                         b=tuple(x[harmonics + 1:]), made=dict(made or {}))


def motion_document(motion: FourierMotion) -> dict:
    """The motion file's JSON object (floats written with repr, so they read back bit for bit)."""
    return {"kind": KIND, "period": motion.period, "q_c": motion.q_c, "a": list(motion.a), "b": list(motion.b),
            "made": dict(motion.made)}


def motion_text(motion: FourierMotion) -> str:
    """The motion file's text: indented JSON and a final newline."""
    return json.dumps(motion_document(motion), indent=2, allow_nan=False) + "\n"


def save_motion(motion: FourierMotion, path, *, overwrite: bool = False) -> None:
    """Write the motion file atomically (jointid.files.atomic_output); ExportError if it cannot."""
    from ..files import atomic_output

    with atomic_output(path, overwrite=overwrite) as handle:
        handle.write(motion_text(motion))


def load_motion(path) -> FourierMotion:
    """Read and check a motion file; MotionFileError (one line naming the file and the problem) if it is bad."""
    # Imported only when a motion file is read.
    from ..files import FileRefused, read_bytes, shown_path

    try:
        raw = read_bytes(path, FILE_SIZE_LIMIT)  # a FIFO or a device is refused before it is opened
    except FileRefused as error:
        raise MotionFileError(f"{shown_path(path)}: cannot read the motion file ({error.reason})") from None
    path = shown_path(path)  # quoted in the messages below if it holds a newline: each stays one line
    if len(raw) > FILE_SIZE_LIMIT:
        raise MotionFileError(f"{path}: larger than {FILE_SIZE_LIMIT:,} bytes; not a motion file")
    try:
        text = raw.decode("utf-8")
        document = json.loads(text, parse_constant=_refuse_constant)
    except UnicodeDecodeError:
        raise MotionFileError(f"{path}: not UTF-8 text; a motion file is JSON") from None
    except json.JSONDecodeError as error:
        raise MotionFileError(f"{path}: not valid JSON ({error.msg} at line {error.lineno}, column {error.colno})") \
            from None
    except ValueError as error:  # NaN / Infinity
        raise MotionFileError(f"{path}: {error}") from None
    except RecursionError:
        raise MotionFileError(f"{path}: nested too deeply; not a motion file") from None
    try:
        return motion_from_document(document)
    except MotionFileError as error:
        raise MotionFileError(f"{path}: {error}") from None


def _refuse_constant(name: str):
    """json's hook for NaN, Infinity and -Infinity, which strict JSON and a motion have no use for."""
    raise ValueError(f"{name} is not a number a motion file may hold")


def motion_from_document(document) -> FourierMotion:
    """Check a parsed motion file's object and build its motion; MotionFileError names the first problem."""
    if not isinstance(document, dict):
        raise MotionFileError(f"the file holds a JSON {type(document).__name__}, not an object with {', '.join(FILE_KEYS)}")
    missing = [key for key in FILE_KEYS if key not in document]
    if missing:
        raise MotionFileError(f"missing key{'s' if len(missing) > 1 else ''} {', '.join(missing)}")
    extra = sorted(set(document) - set(FILE_KEYS))
    if extra:
        raise MotionFileError(f"unknown key{'s' if len(extra) > 1 else ''} {', '.join(map(repr, extra))}")
    if document["kind"] != KIND:
        raise MotionFileError(f"kind must be {KIND!r}; got {document['kind']!r}")
    period = _number(document["period"], "period")
    low, high = PERIOD_LIMITS
    if not low <= period <= high:
        raise MotionFileError(f"period must be from {low:g} to {high:g} s; got {period!r}")
    q_c = _number(document["q_c"], "q_c")
    a, b = (_numbers(document[key], key) for key in ("a", "b"))
    if len(a) != len(b):
        raise MotionFileError(f"a and b must have the same length (one pair per harmonic); got {len(a)} and {len(b)}")
    low, high = HARMONIC_LIMITS
    if not low <= len(a) <= high:
        raise MotionFileError(f"a and b must hold {low} to {high} harmonics; got {len(a)}")
    if not isinstance(document["made"], dict):
        raise MotionFileError(f"made must be an object; got {type(document['made']).__name__}")
    return FourierMotion(period=period, q_c=q_c, a=a, b=b, made=document["made"])


def _number(value, key: str) -> float:
    """A finite JSON number within COEFFICIENT_LIMIT of 0 as a float, or MotionFileError."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise MotionFileError(f"{key} must be a number; got {json.dumps(value)[:40]}")
    try:
        value = float(value)
    except OverflowError:  # a JSON integer of 400 digits
        value = math.inf
    if not math.isfinite(value) or abs(value) > COEFFICIENT_LIMIT:
        raise MotionFileError(f"{key} must be a finite number of magnitude at most {COEFFICIENT_LIMIT:g}; got {value!r}")
    return value


def _numbers(values, key: str) -> tuple[float, ...]:
    """A JSON list of numbers as a tuple of floats, or MotionFileError naming the bad entry."""
    if not isinstance(values, list):
        raise MotionFileError(f"{key} must be a list of numbers; got {json.dumps(values)[:40]}")
    return tuple(_number(value, f"{key}[{index}]") for index, value in enumerate(values))
