"""The library's argument checks: one decorator, `checked`, and the rules it applies to named arguments.

Every public entry point (`jointid.__all__`) declares what each argument must
be; a call with a wrong type raises TypeError and one with a wrong value
ValueError, both naming the function and the argument, before any work (an
AttributeError from deep inside named neither). numpy scalars are numbers like
any other (`np.int64(24)` is a whole number, `np.float32(0.2)` a real one,
`np.bool_(True)` a flag). A rule is any callable `rule(value, where) -> value`
that returns the value to use (converted, e.g. a model name to its model) or
raises; rules for the core's own types live beside those types.
"""

from __future__ import annotations

import functools
import inspect
import math
import numbers
from collections.abc import Callable


def checked(**rules: Callable[[object, str], object]):
    """Decorate a function so that each call checks the named arguments by their rules (given or defaulted)."""

    def decorate(function):
        signature = inspect.signature(function)
        unknown = set(rules) - set(signature.parameters)
        if unknown:  # a typo in a declaration would silently check nothing
            raise TypeError(f"{function.__qualname__} has no argument {', '.join(sorted(unknown))}")

        @functools.wraps(function)
        def wrapper(*args, **kwargs):
            try:
                bound = signature.bind(*args, **kwargs)
            except TypeError as error:
                raise TypeError(f"{function.__name__}(): {error}") from None
            for name, rule in rules.items():
                if name in bound.arguments:
                    bound.arguments[name] = rule(bound.arguments[name], f"{function.__name__}()'s {name}")
            return function(*bound.args, **bound.kwargs)

        wrapper.checked_arguments = tuple(rules)  # what a test of the entry points reads
        return wrapper

    return decorate


def _kind(value) -> str:
    """The type of a value, for messages."""
    return type(value).__name__


def optional(rule: Callable[[object, str], object]) -> Callable[[object, str], object]:
    """A rule that lets None through and applies `rule` to anything else."""

    def check(value, where: str):
        return None if value is None else rule(value, where)

    return check


def instance_of(kind: type, described: str) -> Callable[[object, str], object]:
    """A rule: an instance of `kind` (described for messages as e.g. 'a Settings')."""

    def check(value, where: str):
        if not isinstance(value, kind):
            raise TypeError(f"{where} must be {described}; got {_kind(value)}")
        return value

    return check


def flag_like(value) -> bool:
    """True for Python's and numpy's booleans (numpy's is no subclass of bool, nor a number)."""
    return isinstance(value, bool) or (type(value).__module__ == "numpy" and type(value).__name__ in ("bool", "bool_"))


def flag(value, where: str) -> bool:
    """A rule: True or False (numpy's booleans too); 'no' or 1 are not flags."""
    if flag_like(value):
        return bool(value)
    raise TypeError(f"{where} must be True or False; got {value!r}")


def real(low: float | None = None, high: float | None = None, *, above: bool = False):
    """A rule: a finite real number (numpy's too), at least `low` (above it with `above`) and at most `high`."""

    def check(value, where: str) -> float:
        if flag_like(value) or not isinstance(value, numbers.Real):
            raise TypeError(f"{where} must be a real number; got {_kind(value)}")
        number = float(value)
        if not math.isfinite(number):
            raise ValueError(f"{where} must be a finite number; got {value!r}")
        if low is not None and (number <= low if above else number < low):
            raise ValueError(f"{where} must be {'greater than' if above else 'at least'} {low:g}; got {value!r}")
        if high is not None and number > high:
            raise ValueError(f"{where} must be at most {high:g}; got {value!r}")
        return number

    return check


def whole(low: int | None = None, high: int | None = None):
    """A rule: a whole number (numpy's too, not a bool or a float), from `low` to `high` where given."""

    def check(value, where: str) -> int:
        if flag_like(value) or not isinstance(value, numbers.Integral):
            raise TypeError(f"{where} must be a whole number; got {_kind(value)}")
        number = int(value)
        if (low is not None and number < low) or (high is not None and number > high):
            limits = f"at least {low}" if high is None else f"from {low} to {high}"
            raise ValueError(f"{where} must be a whole number {limits}; got {value!r}")
        return number

    return check


def text(value, where: str) -> str:
    """A rule: a str."""
    if not isinstance(value, str):
        raise TypeError(f"{where} must be a str; got {_kind(value)}")
    return value


def real_array(ndim: int | tuple[int, ...] | None = None, *, finite: bool = True):
    """A rule: array-like real numbers (not complex, text or objects), all finite (with `finite`), with `ndim`
    dimensions where given; returned as a float array."""
    import numpy as np  # only when an array is checked

    dimensions = (ndim,) if isinstance(ndim, int) else ndim

    def check(value, where: str):
        if value is None:
            raise TypeError(f"{where} must be an array of real numbers; got None")
        values = np.asarray(value)
        if values.dtype.kind not in "biuf":
            raise TypeError(f"{where} must be real numbers; got {values.dtype} values")
        values = values.astype(float, copy=False)
        if dimensions is not None and values.ndim not in dimensions:
            shapes = " or ".join(f"{d}-D" for d in dimensions)
            raise ValueError(f"{where} must be {shapes}; got shape {values.shape}")
        if finite and values.size and not np.isfinite(values).all():
            index = np.unravel_index(int(np.flatnonzero(~np.isfinite(values))[0]), values.shape)
            at = "" if not index else f" at index {index[0] if len(index) == 1 else index}"
            raise ValueError(f"{where} must be finite numbers; got {values[index]}{at}")
        return values

    return check


def pairs(value, where: str) -> tuple[tuple[float, float], ...]:
    """A rule: a sequence of (start, end) pairs of real numbers, start <= end (end may be infinite)."""
    if isinstance(value, (str, bytes)) or not isinstance(value, (list, tuple)):
        raise TypeError(f"{where} must be a sequence of (start, end) pairs; got {_kind(value)}")
    result = []
    for item in value:
        if isinstance(item, (str, bytes)) or not isinstance(item, (list, tuple)) or len(item) != 2:
            raise TypeError(f"{where} must hold (start, end) pairs; got {item!r}")
        start, end = item
        if any(flag_like(v) or not isinstance(v, numbers.Real) for v in item):
            raise TypeError(f"{where} must hold pairs of real numbers; got {item!r}")
        start, end = float(start), float(end)
        if math.isnan(start) or math.isnan(end) or math.isinf(start) or not start <= end:
            raise ValueError(f"{where} must hold pairs with a finite start at most the end; got {item!r}")
        result.append((start, end))
    return tuple(result)
