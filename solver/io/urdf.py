"""Export a :class:`Model` to URDF, for robotics tools (pinocchio, placo, ROS, MuJoCo's importer, ...).

The mapping is one to one, because a model link's frame sits at its joint exactly as a URDF child link's:

* every model joint becomes a URDF joint of the same name: ``prismatic`` for the three root translations,
  ``revolute`` otherwise, with its limits, its axis (link frame) and its origin (``origin_position`` and
  ``origin_rotation`` as xyz / rpy in the parent link frame);
* the exterior root chain is kept as it is: the first root joint hangs from a link named ``world``;
* every model link becomes a URDF link of the same name with its mass and center of mass (the inertial
  origin); massless links (the intermediate links of multi-axis joints) have no ``<inertial>``;
* every TCP becomes a link ``tcp_<name>`` on a fixed joint ``tcp_<name>_joint``.

Assumed, because the model does not carry them: the inertia of a link about its center of mass, built
from radii of gyration of 0.30 L across and 0.15 L along the link (about de Leva's 1996 averages for the
limb segments, 0.25-0.33 and 0.10-0.16 of the segment length), L the link's length: the distance from its
joint to its farthest child joint, or twice the center-of-mass offset, at least 2 cm; along = towards that
child (or the center of mass). ``effort`` is the joint's larger muscle strength (N*m; 1000 when unknown)
and ``velocity`` a nominal 10 rad/s (1 m/s for the root translations); kinematics never use either.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from ..body.model import Model
from .files import write_text

RADIUS_ACROSS = 0.30  # radius of gyration across the link, fraction of its length
RADIUS_ALONG = 0.15  # about the link's long axis
MIN_LENGTH = 0.02  # m
DEFAULT_EFFORT = 1000.0  # N*m or N, when the model gives no finite strength
VELOCITY = 10.0  # rad/s; 1 m/s for prismatic joints
WORLD = "world"


def _num(value: float) -> str:
    """A float in short exact-enough text (15 significant digits; tiny values written as 0)."""
    v = float(value)
    if abs(v) < 1e-14:
        return "0"
    return format(v, ".15g")


def _vec(values) -> str:
    return " ".join(_num(v) for v in values)


def rpy_from_matrix(r: np.ndarray) -> np.ndarray:
    """URDF roll, pitch, yaw of a rotation matrix: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    r = np.asarray(r, dtype=float)
    pitch = math.atan2(-r[2, 0], math.hypot(r[0, 0], r[1, 0]))
    if math.hypot(r[0, 0], r[1, 0]) > 1e-9:
        roll = math.atan2(r[2, 1], r[2, 2])
        yaw = math.atan2(r[1, 0], r[0, 0])
    else:  # gimbal lock (pitch = +-90 deg): only roll - yaw (or roll + yaw) is defined; put it all in roll
        yaw = 0.0
        roll = math.atan2(-r[1, 2], r[1, 1])
    return np.array([roll, pitch, yaw])


def matrix_from_rpy(rpy) -> np.ndarray:
    """Inverse of :func:`rpy_from_matrix`: Rz(yaw) Ry(pitch) Rx(roll)."""
    roll, pitch, yaw = (float(a) for a in rpy)
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def link_inertia(model: Model, link: int) -> np.ndarray:
    """Assumed inertia tensor (3x3, kg m^2) of ``link`` about its center of mass, in the link frame."""
    children = np.nonzero(model.parent == link)[0]
    offsets = [model.origin_position[c] for c in children] + [2.0 * model.com[link]]
    lengths = [float(np.linalg.norm(o)) for o in offsets]
    k = int(np.argmax(lengths))
    length = max(lengths[k], MIN_LENGTH)
    along = offsets[k] / lengths[k] if lengths[k] > 1e-9 else np.array([0.0, 0.0, 1.0])
    across2, along2 = (RADIUS_ACROSS * length) ** 2, (RADIUS_ALONG * length) ** 2
    d = np.outer(along, along)
    return model.mass[link] * (across2 * (np.eye(3) - d) + along2 * d)


def _origin(parent: ET.Element, position, rotation: np.ndarray | None = None) -> None:
    attrs = {"xyz": _vec(position)}
    rpy = np.zeros(3) if rotation is None else rpy_from_matrix(rotation)
    attrs["rpy"] = _vec(rpy)
    ET.SubElement(parent, "origin", attrs)


def _link(robot: ET.Element, name: str, model: Model | None = None, index: int = -1) -> None:
    link = ET.SubElement(robot, "link", {"name": name})
    if model is None or model.mass[index] <= 0.0:
        return
    inertial = ET.SubElement(link, "inertial")
    _origin(inertial, model.com[index])
    ET.SubElement(inertial, "mass", {"value": _num(model.mass[index])})
    i = link_inertia(model, index)
    ET.SubElement(
        inertial,
        "inertia",
        {
            "ixx": _num(i[0, 0]),
            "ixy": _num(i[0, 1]),
            "ixz": _num(i[0, 2]),
            "iyy": _num(i[1, 1]),
            "iyz": _num(i[1, 2]),
            "izz": _num(i[2, 2]),
        },
    )


def model_to_urdf(model: Model) -> str:
    """The URDF text (XML) of ``model``; see the module docstring for the mapping and the assumptions."""
    robot = ET.Element("robot", {"name": model.name})
    robot.append(
        ET.Comment(
            f" Manikin model '{model.name}': {model.n} joints, {len(model.tcps)} TCP frames (links tcp_<name>). "
            "Units m, rad, kg. Link inertias are estimates (see solver/io/urdf.py). "
        )
    )
    _link(robot, WORLD)
    for i in range(model.n):
        _link(robot, model.link_names[i], model, i)
    for i in range(model.n):
        kind = "prismatic" if model.prismatic[i] else "revolute"
        joint = ET.SubElement(robot, "joint", {"name": model.joint_names[i], "type": kind})
        _origin(joint, model.origin_position[i], model.origin_rotation[i])
        parent = WORLD if model.parent[i] < 0 else model.link_names[model.parent[i]]
        ET.SubElement(joint, "parent", {"link": parent})
        ET.SubElement(joint, "child", {"link": model.link_names[i]})
        ET.SubElement(joint, "axis", {"xyz": _vec(model.axis[i])})
        strength = model.strength[i][np.isfinite(model.strength[i])]
        effort = float(strength.max()) if strength.size and strength.max() > 0 else DEFAULT_EFFORT
        velocity = 1.0 if model.prismatic[i] else VELOCITY
        ET.SubElement(
            joint,
            "limit",
            {
                "lower": _num(model.lower[i]),
                "upper": _num(model.upper[i]),
                "effort": _num(effort),
                "velocity": _num(velocity),
            },
        )
    for name, tcp in model.tcps.items():
        _link(robot, f"tcp_{name}")
        joint = ET.SubElement(robot, "joint", {"name": f"tcp_{name}_joint", "type": "fixed"})
        _origin(joint, tcp.position, tcp.rotation)
        ET.SubElement(joint, "parent", {"link": model.link_names[tcp.link]})
        ET.SubElement(joint, "child", {"link": f"tcp_{name}"})
    ET.indent(robot, space="  ")
    return '<?xml version="1.0"?>\n' + ET.tostring(robot, encoding="unicode") + "\n"


def write_urdf(model: Model, path: str | Path) -> Path:
    """Write the URDF of ``model`` to ``path`` (parent folders created, atomically); returns the path."""
    return write_text(Path(path), model_to_urdf(model))
