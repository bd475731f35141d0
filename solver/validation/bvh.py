"""A small BVH reader: the hierarchy (joints, offsets, channels and their Euler order per joint), the frames, and
each frame's world joint positions and rotations by forward kinematics.

BVH conventions used (those of the CMU conversions and of Blender's exporter): a joint's rotation channels are
applied in the order listed, each an intrinsic rotation about the joint's current axis, so ``Zrotation Yrotation
Xrotation`` means R = Rz @ Ry @ Rx; angles in degrees; the child's point is parent point + parent rotation @ offset;
the root's position channels are added to its offset. Lengths stay in the file's units (the caller scales them).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import ScenarioError

AXES = {"X": 0, "Y": 1, "Z": 2}


@dataclass
class Joint:
    """One joint: its name, parent index (-1: root), offset (file units) and channel names in file order."""

    name: str
    parent: int
    offset: np.ndarray
    channels: tuple[str, ...] = ()
    end: np.ndarray | None = None  # the End Site's offset, if the joint has one (file units)

    @property
    def rotation_order(self) -> str:
        """The Euler order of the rotation channels as letters, e.g. ``"ZYX"``."""
        return "".join(c[0].upper() for c in self.channels if c.lower().endswith("rotation"))


@dataclass
class Bvh:
    """A parsed file: joints in file order (a parent before its children), frames (frame x channel) and the frame
    time (s)."""

    joints: list[Joint]
    frames: np.ndarray
    frame_time: float
    columns: dict[str, tuple[int, int]] = field(default_factory=dict)  # joint -> (first column, count)

    def index(self, name: str) -> int:
        for i, joint in enumerate(self.joints):
            if joint.name == name:
                return i
        raise KeyError(name)

    def pose(self, frame: int) -> tuple[np.ndarray, np.ndarray]:
        """World rotations (n, 3, 3) and joint points (n, 3, file units) of ``frame`` (None-like rest: see
        :meth:`rest`)."""
        return self._forward(self.frames[frame])

    def rest(self) -> tuple[np.ndarray, np.ndarray]:
        """Rotations and points with every channel zero (the skeleton as its offsets draw it)."""
        return self._forward(np.zeros(self.frames.shape[1] if self.frames.size else self._width()))

    def end_point(self, name: str, rotations: np.ndarray, points: np.ndarray) -> np.ndarray:
        """The End Site point of joint ``name`` for a pose's ``rotations`` and ``points``."""
        i = self.index(name)
        end = self.joints[i].end
        if end is None:
            raise KeyError(f"{name} has no End Site")
        return points[i] + rotations[i] @ end

    def _width(self) -> int:
        return sum(len(j.channels) for j in self.joints)

    def _forward(self, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        n = len(self.joints)
        rotations, points = np.zeros((n, 3, 3)), np.zeros((n, 3))
        for i, joint in enumerate(self.joints):
            first, count = self.columns[joint.name]
            local_r, local_p = channel_transform(joint.channels, values[first : first + count])
            if joint.parent < 0:
                rotations[i], points[i] = local_r, joint.offset + local_p
            else:
                pr = rotations[joint.parent]
                rotations[i] = pr @ local_r
                points[i] = points[joint.parent] + pr @ (joint.offset + local_p)
        return rotations, points


def axis_rotation(axis: str, degrees: float) -> np.ndarray:
    """The 3x3 rotation about ``axis`` ("X", "Y" or "Z") by ``degrees``."""
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    i = AXES[axis.upper()]
    j, k = (i + 1) % 3, (i + 2) % 3
    r = np.eye(3)
    r[j, j], r[j, k], r[k, j], r[k, k] = c, -s, s, c
    return r


def channel_transform(channels: tuple[str, ...], values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A joint's local rotation (rotation channels composed in file order) and translation (position channels)."""
    r, p = np.eye(3), np.zeros(3)
    for name, value in zip(channels, values, strict=True):
        kind = name[1:].lower()
        if kind == "rotation":
            r = r @ axis_rotation(name[0], float(value))
        elif kind == "position":
            p[AXES[name[0].upper()]] = float(value)
    return r, p


def read_bvh(path: str | Path) -> Bvh:
    """Read a BVH file; a ScenarioError names the file and what is wrong."""
    path = Path(path)
    try:
        return parse_bvh(path.read_text())
    except (ValueError, IndexError, KeyError) as exc:
        raise ScenarioError(f"{path}: not a readable BVH file ({exc})") from None


def parse_bvh(text: str) -> Bvh:
    """Parse BVH ``text``; ValueError on a malformed file."""
    tokens = text.split()
    if not tokens or tokens[0] != "HIERARCHY":
        raise ValueError("expected HIERARCHY first")
    joints: list[Joint] = []
    columns: dict[str, tuple[int, int]] = {}
    stack: list[int] = []
    i, width, last = 1, 0, -1
    while tokens[i] != "MOTION":
        tok = tokens[i]
        if tok in ("ROOT", "JOINT"):
            joints.append(Joint(tokens[i + 1], stack[-1] if stack else -1, np.zeros(3)))
            last, i = len(joints) - 1, i + 2
        elif tok == "End":
            i = _end_site(tokens, i, joints[stack[-1]])
            continue
        elif tok == "{":
            stack.append(last)
            i += 1
        elif tok == "}":
            stack.pop()
            i += 1
        elif tok == "OFFSET":
            joints[last].offset = np.array([float(x) for x in tokens[i + 1 : i + 4]])
            i += 4
        elif tok == "CHANNELS":
            count = int(tokens[i + 1])
            joints[last].channels = tuple(tokens[i + 2 : i + 2 + count])
            columns[joints[last].name] = (width, count)
            width, i = width + count, i + 2 + count
        else:
            raise ValueError(f"unexpected token {tok!r}")
    for joint in joints:
        columns.setdefault(joint.name, (width, 0))
    n_frames = int(tokens[tokens.index("Frames:", i) + 1])
    t = tokens.index("Time:", i)
    values = np.array([float(x) for x in tokens[t + 2 :]])
    if values.size != n_frames * width:
        raise ValueError(f"{values.size} values for {n_frames} frames of {width} channels")
    return Bvh(joints, values.reshape(n_frames, width), float(tokens[t + 1]), columns)


def _end_site(tokens: list[str], i: int, joint: Joint) -> int:
    """Read ``End Site { OFFSET x y z }`` at token ``i`` into ``joint``; the index after it."""
    if tokens[i + 1] != "Site" or tokens[i + 2] != "{" or tokens[i + 3] != "OFFSET" or tokens[i + 7] != "}":
        raise ValueError("malformed End Site")
    joint.end = np.array([float(x) for x in tokens[i + 4 : i + 7]])
    return i + 8
