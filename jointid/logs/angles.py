"""A logged angle made continuous before anything is timed or differentiated: wraps undone, far-off turns removed.

Wrapped angles. An encoder or a driver often reports the angle wrapped to
(-pi, pi] or [0, 2 pi): each time the joint passes the seam the log jumps by
a full turn between two samples. Differentiating across such a jump, or
resampling across it, would invent a huge speed, so the wraps are undone
(numpy.unwrap) when the log shows them unmistakably: every value inside one
of the two ranges, some step larger than half a turn, every such step within
a quarter turn of a full turn, and every other step below a quarter turn (so
the joint itself never moves far enough between samples to make the jump).
Any other log is left as it is.

Far-off turns. An angle counted over many turns, or with a large offset, say
2 pi x 1e14, keeps fewer digits: doubles there are 0.125 rad apart, and the
derivatives' differences lose what little is left. Beyond TURN_LIMIT turns
the whole turns are removed: the first sample is reduced to within half a
turn of zero with the platform's exact argument reduction (atan2 of sin and
cos, or fmod in degrees) and every other sample keeps its exact difference
from the first. cos q is unchanged by whole turns, so the fit is too.
"""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np

from .conventions import AngleConvention, AngleReading, logged_angle_name

TURN_LIMIT = 1000
"""Whole turns from zero beyond which they are removed (float64 spacing is then 1e-12 rad and coarser)."""


UNIT_WORDS = {"degrees": {"deg", "degs", "degree", "degrees"}, "radians": {"rad", "rads", "radian", "radians"}}
"""Words in an angle column's name that say its unit ('position_deg', 'angle_rad')."""


def check_angle_unit(table, degrees: bool) -> None:
    """LogError when the angle column's name says one unit and the log is read in the other: a log in degrees read
    as radians fits a joint 57 times too small (and runs of one joint would not pool)."""
    name = dict(table.read_as).get("q", "")
    words = set(re.split(r"[^a-z]+", name.lower()))
    read = "degrees" if degrees else "radians"
    for unit, names in UNIT_WORDS.items():
        if words & names and unit != read:
            from .table import LogError

            how = "give --degrees" if unit == "degrees" else "drop --degrees"
            raise LogError(table.path, f"names its angle column {name!r} in {unit} but it is read in {read}: {how} "
                           "(it applies to every log read; convert a log whose unit differs)")


def read_angle(table, convention: AngleConvention = AngleConvention(), degrees: bool = False):
    """The table with its q column made continuous (wraps undone, far-off turns removed), the convention
    recorded for the pipeline, and a note for each; the same table when there is nothing to do."""
    check_angle_unit(table, degrees)
    angle = table.columns["q"]
    period = 360.0 if degrees else 2 * math.pi
    name = logged_angle_name(table.read_as)
    notes, changed = [], None
    turns = remove_turns(angle, period)
    wraps = None if turns is not None else find_wraps(angle, period)
    reading = AngleReading(convention)
    if turns is not None:
        changed, count = turns
        spacing = float(np.spacing(np.max(np.abs(angle))))
        unit = "°" if degrees else " rad"
        notes.append(f"{name} is {count} whole turns from zero (about {float(angle[0]):.3g}{unit}, where doubles are "
                     f"{spacing:.2g}{unit} apart): the turns are removed, which leaves cos q unchanged.")
        reading = dataclasses.replace(reading, turns_removed=count)
    elif wraps is not None:
        changed, jumps, wrapped = wraps
        notes.append(f"{name} is wrapped to {wrapped}: unwrapped (numpy.unwrap) at {jumps} jump"
                     f"{'s' if jumps != 1 else ''} of nearly a full turn between samples.")
        reading = dataclasses.replace(reading, wraps=jumps, wrapped_range=wrapped)
    note = convention.note(name)
    if note is not None:
        notes.append(note)
    if changed is None and not notes:
        return table
    columns = table.columns if changed is None else {**table.columns, "q": changed}
    return dataclasses.replace(table, columns=columns, notes=(*table.notes, *notes), angle=reading)


def remove_turns(angle: np.ndarray, period: float) -> tuple[np.ndarray, int] | None:
    """(the angle less its whole turns, how many) when it lies more than TURN_LIMIT turns from zero; else None."""
    if len(angle) == 0 or not np.max(np.abs(angle)) > TURN_LIMIT * period:
        return None
    first = float(angle[0])
    if period == 360.0:
        reduced = math.remainder(first, 360.0)  # exact
    else:
        reduced = math.atan2(math.sin(first), math.cos(first))  # sin and cos reduce their argument exactly
    # Differences from the first sample are exact while within a factor of 2 of it (Sterbenz), and no coarser
    # than the samples themselves otherwise.
    changed = (angle - first) + reduced
    return changed, int(round((first - reduced) / period))


def find_wraps(angle: np.ndarray, period: float) -> tuple[np.ndarray, int, str] | None:
    """(the unwrapped angle, the jumps undone, the range it was wrapped to) when the angle is unmistakably
    wrapped (see the module's notes); else None."""
    if len(angle) < 2:
        return None
    half, slack = period / 2, period * 1e-9
    low, high = float(np.min(angle)), float(np.max(angle))
    if low >= -half - slack and high <= half + slack:
        wrapped = "(-180, 180]" if period == 360.0 else "(-pi, pi]"
    elif low >= -slack and high <= period + slack:
        wrapped = "[0, 360)" if period == 360.0 else "[0, 2 pi)"
    else:
        return None
    steps = np.abs(np.diff(angle))
    jumps = steps > half
    if not jumps.any():
        return None
    quarter = period / 4
    if np.any(np.abs(steps[jumps] - period) > quarter) or np.any(steps[~jumps] >= quarter):
        return None
    return np.unwrap(angle, period=period), int(np.count_nonzero(jumps)), wrapped
