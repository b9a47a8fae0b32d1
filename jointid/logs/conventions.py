"""Logs as robots write them: column names, where the logged angle's zero points and which way it grows.

Column names. Besides t, q, qd, qdd and tau, each quantity is recognised by
the names loggers give it (ALIASES), case-insensitively. A name with a suffix
(`position_rad`, `time_s`, `tau_cmd`) is not read unasked: the suffix may name
another unit (`position_deg`, `time_ms`) or another signal (a command beside
the measurement, a second time base beside t), so reading it would be a
guess; when a required column is missing, the message suggests the
--columns map that reads such columns. Two columns giving one quantity (`q`
and `position`) are refused: which one is the angle cannot be guessed. An explicit map (`--columns
q=posn`, `columns=` of fit_log) wins over the names; the columns it leaves
out are still recognised by name.

Angle conventions. jointid's q grows counter-clockwise from world +x (0
points horizontally right), gravity along -y. A log whose angle a has its
zero elsewhere or grows clockwise is converted as q = s a + offset (s = -1
for clockwise; offset 0, pi/2, pi, -pi/2 for a zero pointing right, up,
left, down), and qd, qdd follow with s. So does tau: a logged torque is
positive toward increasing logged angle, which is toward decreasing q when
the angle grows clockwise.

No numpy here: the command line parses --columns and --zero before it loads
anything.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Callable

from .table import COLUMNS

ALIASES = {
    "t": ("t", "time", "timestamp"),
    "q": ("q", "position", "pos", "angle"),
    "qd": ("qd", "velocity", "vel"),
    "qdd": ("qdd", "acceleration", "accel"),
    "tau": ("tau", "torque", "effort"),
}
"""The names each quantity is recognised by (lower case), the canonical one first."""

SPELLINGS = {name: quantity for quantity, names in ALIASES.items() for name in names}
"""Recognised column name (lower case) -> quantity."""


def quantity_of(name: str) -> str | None:
    """The quantity a column name gives (t, q, qd, qdd or tau), or None when it is not recognised."""
    return SPELLINGS.get(str(name).strip().lower())


def _base_name(name: str) -> str:
    """'position_rad' -> 'position': the name before a unit or other suffix."""
    text = str(name).strip().lower()
    for mark in ("_", "[", "(", " "):
        text = text.split(mark, 1)[0]
    return text


def choose(quantity: str, name: str, flag: str = "--columns") -> str:
    """'--columns q=NAME' on the command line, "columns={'q': 'NAME'}" for the library: how to map a column."""
    return f"{flag} {quantity}={name}" if flag.startswith("--") else f"{flag}={{{quantity!r}: {name!r}}}"


def suggested_map(names, found, flag: str = "--columns") -> str:
    """'; read them with --columns t=time_s,q=position_rad' for the quantities not found whose name appears in
    exactly one column with a suffix (a unit, say); '' when there is none. Such columns are never read unasked:
    a suffix may name another unit (position_deg, time_ms) or another signal (tau_cmd beside tau)."""
    pairs = []
    for quantity in COLUMNS:
        if quantity in found:
            continue
        candidates = [str(name) for name in names if quantity_of(name) is None and _base_name(name) in ALIASES[quantity]]
        if len(candidates) == 1:
            pairs.append((quantity, candidates[0]))
    if not pairs:
        return ""
    if flag.startswith("--"):
        how = f"{flag} " + ",".join(f"{key}={name}" for key, name in pairs)
    else:
        how = f"{flag}=" + repr(dict(pairs))
    degrees = any(key == "q" and "deg" in name.lower() for key, name in pairs) and flag.startswith("--")
    names = ", ".join(repr(name) for _, name in pairs)
    return f"; to read {names} (suffixed names are not read unasked), give {how}" + (
        " (and --degrees)" if degrees else "")


class ColumnMapError(ValueError):
    """A column map that cannot be one: not QUANTITY=NAME pairs, an unknown quantity, a quantity twice."""


@dataclass(frozen=True)
class ColumnMap:
    """Which column gives which quantity, named explicitly (`--columns t=time,q=posn`)."""

    pairs: tuple[tuple[str, str], ...]
    """(quantity, column name as given), in the order given."""
    flag: str = "--columns"
    """How messages name the map: the flag, or fit_log's argument."""

    QUANTITIES = COLUMNS
    """The quantities a map may name."""
    EXAMPLE = "t=time,q=position,tau=effort"
    """A map shown in messages."""

    @classmethod
    def parse(cls, text: str, flag: str = "--columns") -> ColumnMap:
        """The map of 'QUANTITY=NAME,...'; ColumnMapError (one line) when it is not one."""
        pairs = []
        for part in str(text).split(","):
            if "=" not in part:
                shown = part.strip() or str(text).strip()
                raise ColumnMapError(f"{shown!r} is not QUANTITY=NAME; give e.g. {cls.EXAMPLE}")
            key, name = (piece.strip() for piece in part.split("=", 1))
            pairs.append((key, name))
        return cls.of_pairs(pairs, flag)

    @classmethod
    def of(cls, given, flag: str = "columns") -> ColumnMap | None:
        """A map from a 'q=position,...' string or a {quantity: name} mapping (None: no map); TypeError or
        ColumnMapError naming `flag`."""
        if given is None or isinstance(given, ColumnMap):
            return given
        try:
            if isinstance(given, str):
                return cls.parse(given, flag)
            if isinstance(given, Mapping):
                return cls.of_pairs([(str(key).strip(), str(name).strip()) for key, name in given.items()], flag)
        except ColumnMapError as error:
            raise ColumnMapError(f"{flag}: {error}") from None
        raise TypeError(f"{flag} must be a mapping of quantity to column name or a 'q=position,...' string; "
                        f"got {type(given).__name__}")

    @classmethod
    def of_pairs(cls, pairs, flag: str = "--columns") -> ColumnMap:
        """The map of (quantity, name) pairs; ColumnMapError for an unknown or repeated quantity, an empty name,
        or one column named for two quantities."""
        seen: dict[str, str] = {}
        for key, name in pairs:
            quantity = key.lower()
            if quantity not in cls.QUANTITIES:
                raise ColumnMapError(f"unknown quantity {key!r} in {key}={name}; the quantities are "
                                     f"{', '.join(cls.QUANTITIES)}")
            if not name:
                raise ColumnMapError(f"{key}= names no column")
            if quantity in seen:
                raise ColumnMapError(f"{quantity} is given twice ({quantity}={seen[quantity]} and {key}={name})")
            other = next((k for k, n in seen.items() if n.lower() == name.lower()), None)
            if other is not None:
                raise ColumnMapError(f"column {name!r} is given for both {other} and {quantity}")
            seen[quantity] = name
        if not seen:
            raise ColumnMapError(f"names no column; give e.g. {cls.EXAMPLE}")
        return cls(tuple(seen.items()), flag)

    @property
    def text(self) -> str:
        """'t=time,q=posn': the map as the flag takes it."""
        return ",".join(f"{key}={name}" for key, name in self.pairs)


class EntryMap(ColumnMap):
    """Which entry of a WPILib data log gives which quantity (`--entry q=/Arm/Position,tau=/Arm/Voltage`): time is
    each record's own time stamp, and `state` names a SysId test-state entry that splits the log into runs."""

    QUANTITIES = ("q", "qd", "qdd", "tau", "state")
    EXAMPLE = "q=/Arm/Position,qd=/Arm/Velocity,tau=/Arm/Voltage"

    @classmethod
    def parse(cls, text: str, flag: str = "--entry") -> EntryMap:
        """The map of 'QUANTITY=ENTRY,...'; ColumnMapError (one line) when it is not one."""
        return super().parse(text, flag)


class ColumnProblem(ValueError):
    """Header names that cannot be read as columns (a map naming a missing column, two columns for one
    quantity); str() is the problem in one line, without the file."""


def match_columns(names, column_map: ColumnMap | None = None, label: Callable[[int], str] | None = None,
                  flag: str = "--columns") -> dict[str, int]:
    """Quantity -> 0-based index in `names` of the column giving it: the map's columns, then every other column
    whose name is recognised (quantity_of); ColumnProblem when a map's column is missing or two columns give
    one quantity. `label(index)` names a column in messages (default: its name quoted); `flag` how to name a map
    when there is none."""
    names = [str(name) for name in names]
    label = label or (lambda index: repr(names[index]))
    found: dict[str, int] = {}
    if column_map is not None:
        lowered = [name.strip().lower() for name in names]
        for key, name in column_map.pairs:
            exact = [i for i, given in enumerate(names) if given == name]
            matches = exact or [i for i, given in enumerate(lowered) if given == name.lower()]
            if not matches:
                shown = ", ".join(names[:20]) + (", …" if len(names) > 20 else "")
                raise ColumnProblem(f"{column_map.flag} {key}={name}: the log has no column {name!r}; its columns "
                                    f"are {shown or 'none'}")
            if len(matches) > 1:
                raise ColumnProblem(f"{column_map.flag} {key}={name}: the log has {len(matches)} columns named "
                                    f"{name!r} (columns {' and '.join(label(i) for i in matches[:2])})")
            found[key] = matches[0]
    explicit = set(found)
    used = set(found.values())
    for index, name in enumerate(names):
        quantity = None if index in used else quantity_of(name)
        if quantity is None or quantity in explicit:
            continue
        if quantity in found:
            first = found[quantity]
            how = choose(quantity, "NAME", flag if column_map is None else column_map.flag)
            raise ColumnProblem(f"columns {label(first)} and {label(index)} both give {quantity}; keep one, or "
                                f"choose one with {how}")
        found[quantity] = index
    return found


def read_as(names, found: dict[str, int]) -> tuple[tuple[str, str], ...]:
    """(quantity, column name) for each quantity found, in COLUMNS order."""
    return tuple((key, str(names[found[key]])) for key in COLUMNS if key in found)


def columns_note(pairs) -> str | None:
    """'columns read as t=time, q=position, ...' when any column is read under a name other than its quantity's
    own; None when every name is t, q, qd, qdd or tau (in any case)."""
    pairs = tuple(pairs)
    if all(name.strip().lower() == key for key, name in pairs):
        return None
    return "columns read as " + ", ".join(f"{key}={name}" for key, name in pairs) + "."


@dataclass(frozen=True)
class LogConventions:
    """How every log of a session is read: its column map and the angle's convention (the explorer's logs opened
    later with Ctrl+O are read as the command line's)."""

    columns: ColumnMap | None = None
    """The CSV column map (`--columns`), or None: by name. A bag's fields have fixed names and take no map."""
    angle: AngleConvention = field(default_factory=lambda: AngleConvention())
    """Where the logged angle's 0 points and which way it grows (`--zero`, `--clockwise`)."""
    effort: object = None
    """What the effort column measured, an effort.EffortReading (`--effort`, `--gear`, `--kt`, `--efficiency`), or
    None: torque."""
    motor: object = None
    """The motors driving the joint, a model.motors.MotorDrive (`--motor`...), or None: for a voltage log's
    physical parameters and a torque log's gains."""

    def request_fields(self, bag: bool = False) -> dict:
        """LoadRequest's `columns`, `angle` (and `effort`, when one is given) for a CSV log, or for a bag (no column
        map)."""
        fields = {"columns": None if bag else self.columns, "angle": self.angle}
        return fields if self.effort is None else {**fields, "effort": self.effort}


# ---------------------------------------------------------------------------------------------- angles

ZEROS = {"right": 0.0, "up": math.pi / 2, "left": math.pi, "down": -math.pi / 2}
"""Where the logged angle's 0 points -> jointid's q there (radians)."""

_PLUS = {"right": "", "up": " + pi/2", "left": " + pi", "down": " - pi/2"}
_MINUS = {"right": "-{a}", "up": "pi/2 - {a}", "left": "pi - {a}", "down": "-pi/2 - {a}"}


@dataclass(frozen=True)
class AngleConvention:
    """Where a log's angle 0 points and which way it grows: q = sign * angle + offset."""

    zero: str = "right"
    """'right' (jointid's own q = 0), 'up', 'left' or 'down'."""
    clockwise: bool = False
    """True when the logged angle grows clockwise."""

    def __post_init__(self):
        if self.zero not in ZEROS:
            raise ValueError(f"zero must be one of {', '.join(ZEROS)}; got {self.zero!r}")

    @property
    def sign(self) -> int:
        """-1 when the angle grows clockwise, else 1: the factor on the angle, its derivatives and the torque."""
        return -1 if self.clockwise else 1

    @property
    def offset(self) -> float:
        """jointid's q (radians) where the logged angle is 0."""
        return ZEROS[self.zero]

    @property
    def is_default(self) -> bool:
        """True for jointid's own convention (nothing to convert)."""
        return self.zero == "right" and not self.clockwise

    def formula(self, angle: str = "position") -> str:
        """'q = position - pi/2': q from the logged angle, in radians."""
        return "q = " + (f"{angle}{_PLUS[self.zero]}" if not self.clockwise else _MINUS[self.zero].format(a=angle))

    def note(self, angle: str = "position") -> str | None:
        """The conversion in one sentence for a person; None for jointid's own convention."""
        if self.is_default:
            return None
        turning = "clockwise" if self.clockwise else "counter-clockwise"
        text = f"angle 0 pointing {self.zero}, {turning}: {self.formula(angle)}"
        if self.clockwise:
            text += (", and qd, qdd and tau change sign (a torque the log calls positive turns toward "
                     "increasing logged angle, which is decreasing q)")
        return text + "."

    def to_dict(self, angle: str = "position") -> dict:
        """JSON-ready: zero, clockwise, and q = sign * angle + offset_rad."""
        return {"zero": self.zero, "clockwise": self.clockwise, "sign": self.sign, "offset_rad": self.offset,
                "q_from_log": self.formula(angle)}


@dataclass(frozen=True)
class AngleReading:
    """How a log's angle was read: its convention, and any wraps undone or whole turns removed."""

    convention: AngleConvention = field(default_factory=AngleConvention)
    wraps: int = 0
    """Jumps of nearly a full turn undone (numpy.unwrap); 0 when the angle was not wrapped."""
    wrapped_range: str | None = None
    """'(-pi, pi]' or '[0, 2 pi)' (in degrees '(-180, 180]', '[0, 360)') when the angle was unwrapped."""
    turns_removed: int = 0
    """Whole turns taken off an angle logged far from zero."""

    def to_dict(self, angle: str) -> dict:
        """JSON-ready: the convention, the wraps undone and the turns removed."""
        return {**self.convention.to_dict(angle), "unwrapped_jumps": self.wraps,
                "wrapped_range": self.wrapped_range, "turns_removed": self.turns_removed}


def logged_angle_name(pairs) -> str:
    """How notes name the logged angle: its column's name ('position'), or 'logged q' for a column named q."""
    name = dict(pairs).get("q", "q")
    return "logged q" if name.strip().lower() == "q" else name
