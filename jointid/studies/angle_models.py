"""Whether a log's q is an angle a model may take cos(q) of: a data log's length (metres) or a velocity-only
routine's integrated velocity is not, and a gravity term on it would fit a cosine of metres."""

from __future__ import annotations

from ..logs.pipeline import JointLog
from ..logs.table import LogError
from ..model.terms import JointModel


def no_angle(log: JointLog) -> str | None:
    """Why the log's q is no absolute angle in radians ("a length in metres", "the logged velocity integrated"),
    or None when it is one."""
    table = None if log.source is None else log.source.table
    if getattr(table, "position_source", "logged") != "logged":
        return "the logged velocity integrated (no position was logged)"
    if getattr(table, "linear", False):
        return "a length in metres"
    return None


def check_angle_model(log: JointLog, model: JointModel) -> None:
    """LogError when the model takes cos(q) or sin(q) of a log whose q is no angle in radians."""
    reason = no_angle(log)
    if reason is not None and any(term.kind in ("h", "h_c", "h_s") for term in model.terms):
        raise LogError(log.path, f"--model {model.name}: its gravity term takes cos(q), and q here is "
                       f"{reason}, not an angle in radians; leave --model out (kA, kV and kS, no gravity)")
