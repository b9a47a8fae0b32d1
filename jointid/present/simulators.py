"""A rigid link as simulators read it: MuJoCo's MJCF, URDF, and the text `jointid export` prints about them.

Both files hold one body on one hinge about its link frame's y axis, the link
moving in the x-z plane with gravity along -z (model.rigid_link says why).
Only the inertia about the hinge axis is identified; the other two principal
moments, which one hinge cannot reveal, are a flat plate's in the plane of
motion (half the moment about the axis each, which any in-plane direction of
the centre of mass keeps and which satisfies the triangle inequality that
MuJoCo checks). Numbers are written as Python's shortest repr, so that parsing
a file back gives the very doubles exported. The XML is built with the
standard library's ElementTree, which escapes names and values.
"""

from __future__ import annotations

import math
import textwrap
import xml.etree.ElementTree as ET
from collections.abc import Mapping

from ..model.rigid_link import RigidLink
from ..model.terms import G
from ..text_safety import shown_name
from .text import format_number, join_words

ROD_THICKNESS = 0.05
"""A drawn rod's radius as a fraction of its length (drawing only: the body's inertia is the <inertial>'s)."""

COMMENT_WIDTH = 100
"""Width of the files' opening comment."""

FORMATS = {"mujoco": "MuJoCo MJCF", "urdf": "URDF"}
"""Export formats, by their flag's name, with how texts name them."""


def number(value: float) -> str:
    """A float as XML attributes hold it: the shortest text that reads back as the same double ('0.2', '1e-05')."""
    value = float(value)
    if value.is_integer() and abs(value) < 1e15:
        return str(int(value))  # '2', '-1', '0' rather than '2.0', '-1.0', '-0.0'
    return repr(value)


def numbers(values) -> str:
    """Several numbers separated by spaces, as MJCF's and URDF's vector attributes take them."""
    return " ".join(number(value) for value in values)


def _comment_text(text: str, indent: str) -> str:
    """Text an XML comment can hold (no '--', printable characters), each paragraph wrapped at COMMENT_WIDTH."""
    text = "".join(c if c.isprintable() or c == "\n" else repr(c)[1:-1] for c in text)
    while "--" in text:
        text = text.replace("--", "- -")
    lines = [line for paragraph in text.rstrip("-").split("\n")
             for line in textwrap.wrap(paragraph, COMMENT_WIDTH, break_on_hyphens=False)]
    return "\n".join([""] + [indent + "  " + line for line in lines] + [indent])


def provenance(link: RigidLink, source: str) -> str:
    """The files' opening comment: where the numbers come from and how the link was derived."""
    x, _, z = link.com_position
    armature = f" - armature {link.armature:.6g}" if link.armature > 0 else ""  # the armature stays at the joint
    turning = "-y: counter-clockwise seen from +y" if link.axis_sign > 0 else "+y: clockwise seen from +y"
    return (f"Exported by jointid from {source}.\n"
            f"I = {link.joint_inertia:.6g} kg m^2 and h = {link.mass_moment:.6g} kg m fix the link only with its "
            f"mass m = {link.mass:.6g} kg: the centre of mass lies r = h/m = {link.com_distance:.6g} m from the axis "
            f"(x = {x:.6g}, z = {z:.6g}), and the inertia about it is I{armature} - m r^2 = "
            f"{link.inertia_about_com:.6g} kg m^2.\n"
            f"The joint turns about {turning}; gravity {G:g} m/s^2 along -z. Only the moment about the axis is "
            "identified: the other two are a flat plate's in the plane of motion.")


def mjcf_text(link: RigidLink, name: str = "joint", source: str = "a jointid fit") -> str:
    """The MJCF model: the hinge (damping, frictionloss when there is friction, armature), the body's
    <inertial> about its centre of mass, a rod drawn to the centre of mass (no collisions), a torque motor."""
    root = ET.Element("mujoco", model=name)
    root.append(ET.Comment(_comment_text(provenance(link, source), "  ")))
    ET.SubElement(root, "option", gravity=numbers((0.0, 0.0, -G)))
    world = ET.SubElement(root, "worldbody")
    body = ET.SubElement(world, "body", name=f"{name}_link")
    joint = {"name": name, "type": "hinge", "axis": numbers(link.axis), "damping": number(link.damping)}
    if link.friction > 0:
        joint["frictionloss"] = number(link.friction)
    joint["armature"] = number(link.armature)
    ET.SubElement(body, "joint", joint)
    moment = link.inertia_about_com
    ET.SubElement(body, "inertial", pos=numbers(link.com_position), mass=number(link.mass),
                  diaginertia=numbers((moment / 2, moment, moment / 2)))
    rod = _rod_end(link)
    if rod is not None:
        end, radius = rod
        ET.SubElement(body, "geom", name=f"{name}_rod", type="capsule", fromto=numbers((0.0, 0.0, 0.0, *end)),
                      size=number(radius), contype="0", conaffinity="0", rgba="0.8 0.5 0.2 1")
    actuators = ET.SubElement(root, "actuator")
    ET.SubElement(actuators, "motor", name=f"{name}_motor", joint=name)
    return _xml_text(root, declaration=False)


def urdf_text(link: RigidLink, name: str = "joint", source: str = "a jointid fit") -> str:
    """The URDF robot: a fixed base, the link's <inertial> about its centre of mass and a drawn rod, and a
    continuous joint with <dynamics damping friction>. URDF has no armature: a motor's rotor inertia is added to
    the link's moment about the axis, which gives the joint the same dynamics."""
    root = ET.Element("robot", name=name)
    text = provenance(link, source)
    if link.armature > 0:
        text += (f"\nURDF has no armature: the rotor's {number(link.armature)} kg m^2 is added to the link's "
                 "moment about the axis (iyy).")
    root.append(ET.Comment(_comment_text(text, "  ")))
    ET.SubElement(root, "link", name=f"{name}_base")
    body = ET.SubElement(root, "link", name=f"{name}_link")
    inertial = ET.SubElement(body, "inertial")
    ET.SubElement(inertial, "origin", xyz=numbers(link.com_position), rpy="0 0 0")
    ET.SubElement(inertial, "mass", value=number(link.mass))
    moment = link.inertia_about_com + link.armature
    ET.SubElement(inertial, "inertia", ixx=number(moment / 2), ixy="0", ixz="0", iyy=number(moment), iyz="0",
                  izz=number(moment / 2))
    rod = _rod_end(link)
    if rod is not None:
        (x, _, z), radius = rod
        visual = ET.SubElement(body, "visual")
        # A cylinder stands along z: turned about y by atan2(x, z) it points from the axis to (x, 0, z).
        ET.SubElement(visual, "origin", xyz=numbers((x / 2, 0.0, z / 2)), rpy=numbers((0.0, math.atan2(x, z), 0.0)))
        geometry = ET.SubElement(visual, "geometry")
        ET.SubElement(geometry, "cylinder", radius=number(radius), length=number(math.hypot(x, z)))
    joint = ET.SubElement(root, "joint", name=name, type="continuous")
    ET.SubElement(joint, "parent", link=f"{name}_base")
    ET.SubElement(joint, "child", link=f"{name}_link")
    ET.SubElement(joint, "origin", xyz="0 0 0", rpy="0 0 0")
    ET.SubElement(joint, "axis", xyz=numbers(link.axis))
    ET.SubElement(joint, "dynamics", damping=number(link.damping), friction=number(link.friction))
    return _xml_text(root, declaration=True)


def _rod_end(link: RigidLink) -> tuple[tuple[float, float, float], float] | None:
    """The drawn rod's far end (along the centre of mass's direction, to --length or to the centre of mass) and
    its radius; None when it would have no length."""
    reach = link.length if link.length is not None else link.com_distance
    if not reach > 0:
        return None
    return tuple(reach * component for component in link.direction), float(f"{ROD_THICKNESS * reach:.3g}")


def _xml_text(root: ET.Element, declaration: bool) -> str:
    """The element as indented XML text ending in a newline (with an <?xml?> declaration for URDF)."""
    ET.indent(root, space="  ")
    text = ET.tostring(root, encoding="unicode")
    return ('<?xml version="1.0" encoding="utf-8"?>\n' if declaration else "") + text + "\n"


def parameters_line(parameters: Mapping[str, float], model: str) -> str:
    """'Identified (model plain): I 0.800000 kg m², h 0.400000 kg m, B 0.150000 N m s/rad.'"""
    units = {"I": "kg m²", "h": "kg m", "B": "N m s/rad", "Fc": "N m", "q0": "rad", "tau0": "N m"}
    shown = ", ".join(f"{name} {format_number(value)} {units.get(name, '')}".rstrip()
                      for name, value in parameters.items())
    return f"Identified (model {model}): {shown}."


def export_text(link: RigidLink, parameters: Mapping[str, float], model: str, written: Mapping[str, str], *,
                mass_given: bool, convention: str) -> str:
    """What `jointid export` prints: the identified parameters, the link derived from them, what was left out,
    the joint's angle convention, and the files written ({format: path})."""
    if mass_given:
        where = f"mass {link.mass:.6g} kg (given), centre of mass {link.com_distance:.6g} m from the axis (h/m)"
    else:
        where = f"centre of mass {link.com_distance:.6g} m from the axis (given), mass {link.mass:.6g} kg (h/r)"
    minus = "I - armature - h²/m" if link.armature > 0 else "I - h²/m"
    friction = f"friction {link.friction:.6g} N m" if "Fc" in parameters else "no friction (the model has none)"
    lines = [parameters_line(parameters, model),
             f"Link: {where}, inertia about the centre of mass {link.inertia_about_com:.6g} kg m² ({minus}).",
             (f"Joint: damping {link.damping:.6g} N m s/rad, {friction}, armature {link.armature:.6g} kg m²; "
              f"{convention}.")]
    if "tau0" in parameters:
        lines.append("Not exported: the torque bias tau0, a property of the torque sensor, not of the joint.")
    if link.mass_moment > 0:
        lines.append(f"Small swings about hanging straight down: period 2 pi sqrt(I/(h g)) = "
                     f"{link.small_swing_period:.4f} s without damping.")
    files = [f"{shown_name(path)} ({FORMATS[kind]})" for kind, path in written.items()]
    lines.append(f"Wrote {join_words(files)}.")
    return "\n".join(lines)


def export_document(link: RigidLink, parameters: Mapping[str, float], model: str, source: str,
                    written: Mapping[str, str], not_determined: tuple[str, ...]) -> dict:
    """`jointid export --json`: the identified parameters, the link derived from them (SI units: kg, m, kg m², N m
    s/rad, N m), the files."""
    return {
        "source": source,
        "model": model,
        "estimate": dict(parameters),
        "not_determined": list(not_determined),
        "link": {"mass": link.mass, "com_distance": link.com_distance, "com_position": list(link.com_position),
                 "inertia_about_com": link.inertia_about_com, "joint_inertia": link.joint_inertia,
                 "mass_moment": link.mass_moment, "axis": list(link.axis), "damping": link.damping,
                 "friction": link.friction, "armature": link.armature, "length": link.length},
        "files": dict(written),
    }


def mujoco_check_text(check, path: str) -> str:
    """The line `jointid export --check` prints: what MuJoCo reads back from the MJCF, beside the identified."""
    read = (f"MuJoCo {check.version} loads {path}: inertia about the joint {check.joint_inertia:.6g} kg m², torque "
            f"to hold the link level {check.gravity_torque:.6g} N m")
    if check.agrees:
        return f"{read}, as identified (I and h g)."
    return (f"{read}, not the identified I {check.expected_inertia:.6g} kg m² and h g {check.expected_torque:.6g} "
            "N m: the exported file is wrong; please report it.")


def undetermined_warning(names: tuple[str, ...]) -> str:
    """The one stderr line when exported parameters are not determined by the fit."""
    verb, them = ("is", "it") if len(names) == 1 else ("are", "them")
    return (f"jointid export: warning: {join_words(list(names))} {verb} not determined by this fit (standard error "
            f"above 30 %); the files hold {them} all the same")


def convention_text(zero: str, clockwise: bool) -> str:
    """How the exported joint's value reads: 'its 0 is jointid's q = 0 (horizontal), counter-clockwise'."""
    if zero == "right" and not clockwise:
        return "its 0 points horizontally (jointid's q = 0) and it grows counter-clockwise, upward from there"
    turning = "clockwise" if clockwise else "counter-clockwise"
    return f"its 0 points {zero} and it grows {turning}, as the log's angle does"
