"""The rigid link behind I and h: the split the test does itself (r = h/m, I_com = I - m r²), the direction of the
centre of mass, and the links no body can be, each refused in one line."""

from __future__ import annotations

import math

import pytest

from jointid.model.rigid_link import LinkError, split_link


def test_a_mass_or_a_distance_splits_i_and_h_by_parallel_axes():
    link = split_link(0.8, 0.4, 0.15, 0.2, mass=2.0)
    assert (link.mass, link.com_distance, link.damping, link.friction) == (2.0, 0.2, 0.15, 0.2)
    assert link.inertia_about_com == pytest.approx(0.8 - 2.0 * 0.2**2, rel=1e-15)
    assert link.com_position == (0.2, 0.0, 0.0) and link.axis == (0.0, -1.0, 0.0)
    same = split_link(0.8, 0.4, 0.15, com_distance=0.2)
    assert same.mass == pytest.approx(2.0, rel=1e-15) and same.inertia_about_com == pytest.approx(0.72, rel=1e-14)
    assert link.small_swing_period == pytest.approx(2 * math.pi * math.sqrt(0.8 / (0.4 * 9.81)), rel=1e-15)


def test_armature_leaves_the_body_and_the_joint_keeps_the_whole_inertia():
    link = split_link(0.8, 0.4, 0.15, mass=2.0, armature=0.1)
    assert link.inertia_about_com == pytest.approx(0.8 - 0.1 - 0.08, rel=1e-14)
    assert link.joint_inertia == pytest.approx(0.8, rel=1e-15)


@pytest.mark.parametrize("h, q0, zero, sign, expected", [
    (-0.4, 0.0, 0.0, 1, (-0.2, 0.0, 0.0)),  # h < 0: the centre of mass on the other side of the axis
    (0.4, 0.3, 0.0, 1, (0.2 * math.cos(0.3), 0.0, 0.2 * math.sin(0.3))),  # gravity torque h g cos(q + q0)
    (0.4, 0.0, -math.pi / 2, 1, (0.0, 0.0, -0.2)),  # the log's 0 points down: at joint value 0 it hangs
    (0.4, 0.0, math.pi / 2, -1, (0.0, 0.0, 0.2)),  # 0 up, clockwise: it stands, and the axis is +y
])
def test_the_centre_of_mass_points_where_the_gravity_torque_says(h, q0, zero, sign, expected):
    link = split_link(0.8, h, 0.15, angle_offset=q0, mass=2.0, zero_offset=zero, axis_sign=sign)
    assert link.com_position == pytest.approx(expected, abs=1e-15)
    assert link.axis == (0.0, -float(sign), 0.0)
    assert link.mass_moment == pytest.approx(abs(h), rel=1e-15)


@pytest.mark.parametrize("arguments, expected", [
    ({"mass": 0.19}, "--mass 0.19 kg is too small"),
    ({"com_distance": 2.5}, "--com-distance 2.5 m is too far"),
    ({"mass": 1.0, "length": 0.3}, "beyond --length 0.3 m"),
    ({}, "give exactly one of --mass and --com-distance"),
    ({"mass": 1.0, "com_distance": 0.4}, "give exactly one of --mass and --com-distance"),
    ({"mass": 1.0, "armature": 0.8}, "--armature 0.8 kg m² must be 0 or more and less than I"),
    ({"mass": 0.25, "armature": 0.2}, "the mass must exceed h²/(I - armature) = 0.266667 kg"),
])
def test_a_link_no_body_can_be_is_refused_in_one_line(arguments, expected):
    with pytest.raises(LinkError) as refusal:
        split_link(0.8, 0.4, 0.15, **arguments)
    assert expected in str(refusal.value) and "\n" not in str(refusal.value)


@pytest.mark.parametrize("inertia, h, damping, friction, expected", [
    (-0.1, 0.4, 0.15, 0.0, "I = -0.1 kg m² is not positive"),
    (0.8, 0.4, -0.01, 0.0, "B = -0.01 N m s/rad is negative"),
    (0.8, 0.4, 0.15, -0.2, "Fc = -0.2 N m is negative"),
    (math.nan, 0.4, 0.15, 0.0, "I is nan, not a finite number"),
    (0.8, math.inf, 0.15, 0.0, "h is inf, not a finite number"),
])
def test_parameters_a_simulator_cannot_take_are_refused(inertia, h, damping, friction, expected):
    with pytest.raises(LinkError, match=expected.replace("(", r"\(")):
        split_link(inertia, h, damping, friction, mass=2.0)


def test_a_centre_of_mass_on_the_axis_needs_the_mass():
    assert split_link(0.8, 0.0, 0.15, mass=2.0).com_distance == 0.0
    with pytest.raises(LinkError, match="h = 0"):
        split_link(0.8, 0.0, 0.15, com_distance=0.1)
