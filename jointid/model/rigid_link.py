"""The rigid link behind an identified joint, for a simulator: mass, centre of mass, inertia about it.

A joint's dynamics reveal only I (the inertia about the axis) and h = m r (the
gravity mass moment), never m, r and the inertia about the centre of mass
I_com apart: any mass m gives r = h/m and I_com = I - m r² = I - h²/m with
the same I and h (the lesson's point). So a link needs one more number, the
mass or the centre of mass's distance, and some of those numbers describe no
body: I_com < 0 (the mass too small for I and h), a centre of mass beyond the
link's length. `split_link` refuses those with a one-line LinkError.

Geometry, in the link's own frame as simulators take it (gravity along -z):
the joint turns about y, and the link moves in the x-z plane. jointid's plane
(x right, y up, q counter-clockwise from +x) is the simulator's x-z plane, so
a counter-clockwise turn is about -y. The joint's 0 and direction are the
log's own when it was read with --zero/--clockwise (`angle_offset`,
`axis_sign`), so a controller written for the robot reads the simulated
joint the same way.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .terms import G


class LinkError(ValueError):
    """Parameters that make no rigid link; str() is one line saying which and why."""


@dataclass(frozen=True)
class RigidLink:
    """One rigid link on one hinge: what a simulator's body and joint need (SI units)."""

    mass: float
    """m (kg), greater than 0."""
    com_distance: float
    """r (m), the centre of mass's distance from the axis, 0 or more."""
    com_angle: float
    """(rad) Where the centre of mass lies in the link's x-z plane, from +x toward +z at joint value 0."""
    inertia_about_com: float
    """I_com (kg m²) about the axis through the centre of mass parallel to the joint's, greater than 0."""
    damping: float
    """B (N m s/rad), 0 or more."""
    friction: float = 0.0
    """Fc (N m), the Coulomb friction torque, 0 or more."""
    armature: float = 0.0
    """The part of I that is a motor's reflected rotor inertia (kg m²), which simulators add at the joint."""
    axis_sign: int = 1
    """1: the joint's value grows counter-clockwise as jointid's q does (axis -y); -1: clockwise (axis +y)."""
    length: float | None = None
    """The link's length (m) when known, for drawing it; None: drawn to the centre of mass."""

    @property
    def direction(self) -> tuple[float, float, float]:
        """The unit vector from the axis toward the centre of mass in the link's frame at joint value 0."""
        return (_snapped(math.cos(self.com_angle)), 0.0, _snapped(math.sin(self.com_angle)))

    @property
    def com_position(self) -> tuple[float, float, float]:
        """(x, y, z) of the centre of mass in the link's frame at joint value 0 (m)."""
        return tuple(self.com_distance * component for component in self.direction)

    @property
    def axis(self) -> tuple[float, float, float]:
        """The joint axis in the link's frame: -y for counter-clockwise, +y for clockwise."""
        return (0.0, -float(self.axis_sign), 0.0)

    @property
    def joint_inertia(self) -> float:
        """I about the joint axis: I_com + m r² + armature (kg m²), the identified inertia."""
        return self.inertia_about_com + self.mass * self.com_distance**2 + self.armature

    @property
    def mass_moment(self) -> float:
        """h = m r (kg m), the identified gravity mass moment (its direction is com_angle's)."""
        return self.mass * self.com_distance

    @property
    def small_swing_period(self) -> float:
        """2 pi sqrt(I / (h g)) (s): the undamped period of a small swing about hanging straight down."""
        return 2 * math.pi * math.sqrt(self.joint_inertia / (self.mass_moment * G)) if self.mass_moment > 0 \
            else math.inf


def split_link(inertia: float, mass_moment: float, damping: float, friction: float = 0.0, angle_offset: float = 0.0,
               *, mass: float | None = None, com_distance: float | None = None, length: float | None = None,
               armature: float = 0.0, zero_offset: float = 0.0, axis_sign: int = 1) -> RigidLink:
    """The rigid link with the identified I, h, B, Fc (and angle offset q0) and the given mass or centre of mass
    distance; LinkError (one line) when no body has them.

    `mass` or `com_distance` (exactly one) supplies what I and h cannot; `length` (optional) is the link's, which
    the centre of mass must lie within; `armature` is the part of I that a motor's rotor brings (kept at the
    joint, not in the body). A negative h puts the centre of mass on the other side of the axis. `zero_offset` and
    `axis_sign` are the log's angle convention (q = axis_sign * angle + zero_offset): the joint's 0 is then where
    the log's angle was 0.
    """
    _check_inputs(inertia, mass_moment, damping, friction, angle_offset, mass, com_distance, length, armature)
    moment = abs(mass_moment)
    given_mass = mass is not None
    if mass is None:
        if moment == 0:
            raise LinkError("h = 0: the centre of mass is on the axis, so --com-distance cannot give the mass; "
                            "give --mass")
        mass = moment / com_distance
    else:
        com_distance = moment / mass
    if length is not None and com_distance > length:
        hint = f"; the mass must be at least h/length = {moment / length:.6g} kg" if given_mass else ""
        raise LinkError(f"the centre of mass would lie {com_distance:.6g} m from the axis, beyond --length "
                        f"{length:.6g} m{hint}")
    body_inertia = inertia - armature
    inertia_about_com = body_inertia - moment * com_distance  # I - m r² = I - h r, without squaring a large r
    if not inertia_about_com > 0:
        raise LinkError(_no_body(inertia, mass_moment, armature, mass if given_mass else None, com_distance,
                                 inertia_about_com))
    direction = zero_offset + angle_offset + (math.pi if mass_moment < 0 else 0.0)
    return RigidLink(mass=mass, com_distance=com_distance, com_angle=_wrapped(direction),
                     inertia_about_com=inertia_about_com, damping=damping, friction=friction, armature=armature,
                     axis_sign=1 if axis_sign >= 0 else -1, length=length)


def _check_inputs(inertia, mass_moment, damping, friction, angle_offset, mass, com_distance, length, armature) -> None:
    """LinkError for a value no simulator takes, whatever the split: not finite, I not positive, negative damping
    or friction, an armature beyond I, neither or both of the mass and the distance."""
    values = {"I": inertia, "h": mass_moment, "B": damping, "Fc": friction, "q0": angle_offset,
              "--mass": mass, "--com-distance": com_distance, "--length": length, "--armature": armature}
    for name, value in values.items():
        if value is not None and not math.isfinite(value):
            raise LinkError(f"{name} is {value}, not a finite number: no link to export")
    if (mass is None) == (com_distance is None):
        raise LinkError("give exactly one of --mass and --com-distance: I and h alone do not fix the link's mass")
    if not inertia > 0:
        raise LinkError(f"I = {inertia:.6g} kg m² is not positive: no body has it (fit with --constrained, or "
                        "with a motion that reveals I)")
    for name, value, unit in (("B", damping, "N m s/rad"), ("Fc", friction, "N m")):
        if value < 0:
            raise LinkError(f"{name} = {value:.6g} {unit} is negative: a simulator's damping and friction only "
                            "take energy away (fit with --constrained)")
    if armature < 0 or armature >= inertia:
        raise LinkError(f"--armature {armature:.6g} kg m² must be 0 or more and less than I = {inertia:.6g} kg m²")
    for name, value in (("--mass", mass), ("--com-distance", com_distance), ("--length", length)):
        if value is not None and not value > 0:
            raise LinkError(f"{name} {value:.6g} must be greater than 0")


def _no_body(inertia: float, mass_moment: float, armature: float, mass: float | None, com_distance: float,
             inertia_about_com: float) -> str:
    """The one line refusing a split whose inertia about the centre of mass is not positive (`mass` None: the
    distance was given)."""
    moment, body_inertia = abs(mass_moment), inertia - armature
    inertia_name = "I - armature" if armature > 0 else "I"
    divisor = f"({inertia_name})" if armature > 0 else inertia_name
    given = f"I = {inertia:.6g} kg m²" + (f", armature {armature:.6g} kg m²" if armature > 0 else "")
    if mass is not None:
        return (f"--mass {mass:.6g} kg is too small for {given} and h = {mass_moment:.6g} kg m: the inertia about "
                f"the centre of mass, {inertia_name} - h²/m, would be {inertia_about_com:.6g} kg m², which no body "
                f"has; the mass must exceed h²/{divisor} = {moment**2 / body_inertia:.6g} kg")
    return (f"--com-distance {com_distance:.6g} m is too far for {given} and h = {mass_moment:.6g} kg m: the inertia "
            f"about the centre of mass, {inertia_name} - h r, would be {inertia_about_com:.6g} kg m², which no body "
            f"has; the centre of mass must lie within {divisor}/h = {body_inertia / moment:.6g} m")


def _wrapped(angle: float) -> float:
    """The angle in (-pi, pi], exactly 0 for 0 (so that a link along +x is written as x = r, z = 0)."""
    wrapped = math.remainder(angle, 2 * math.pi)
    return math.pi if wrapped == -math.pi else wrapped


def _snapped(component: float) -> float:
    """A cosine or sine of a quarter turn is exactly 0, not cos(pi/2) = 6e-17 (a centre of mass straight down is
    written as x = 0)."""
    return 0.0 if abs(component) < 1e-15 else component
