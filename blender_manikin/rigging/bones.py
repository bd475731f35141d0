"""How a solver Model maps onto an armature: bones, rest frames, pose channels. Plain NumPy, no bpy.

One bone per *joint group*: consecutive joints of one chain at one point (a vertebra's rx/ry/rz, a hip's three
rotations, the exterior root's three slides and three turns). The bone is named after the group's last link and
its frame is that link's frame, axes permuted so the bone's y axis runs along the body segment. Because the
permutation is signed and the joint axes are basis axes, every revolute joint is one Euler channel of the bone
(rotation mode = the joints' order) and every prismatic joint one location channel, so a pose is written and
read back exactly as joint values. Groups whose axes are not basis axes fall back to quaternions, written from
the solver's link frames.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # plain NumPy at run time, so the layout is testable without bpy or the package context
    from ...solver.body.model import Kinematics, Model

LETTERS = "XYZ"
MIN_LENGTH = 0.01  # m, shortest bone
_EPS = 1e-9


@dataclass(frozen=True)
class Channel:
    """Joint ``joint`` drives ``prop[index]`` of its pose bone as ``sign * value``."""

    joint: int
    prop: str  # "rotation_euler" or "location"
    index: int
    sign: float


@dataclass(frozen=True)
class BoneSpec:
    """A bone in armature space (zero pose): ``rest`` columns are its x, y (along the bone), z axes."""

    name: str
    parent: int  # bone index, -1 for the root bone
    joints: tuple[int, ...]
    link: int  # the group's last link: the bone frame moves with it
    head: np.ndarray
    length: float
    rest: np.ndarray
    rotation_mode: str  # Blender rotation mode: "ZYX" etc., or "QUATERNION"
    channels: tuple[Channel, ...]
    lock_location: tuple[bool, bool, bool]
    lock_rotation: tuple[bool, bool, bool]
    segment_end: np.ndarray  # zero-pose end of the visible segment (m)
    mass: float  # kg of the group's links

    @property
    def exact(self) -> bool:
        """True when every joint of the bone is one channel (Euler mode)."""
        return self.rotation_mode != "QUATERNION"

    @property
    def tail(self) -> np.ndarray:
        return self.head + self.rest[:, 1] * self.length

    def matrix(self) -> np.ndarray:
        """4x4 rest matrix in armature space."""
        m = np.eye(4)
        m[:3, :3], m[:3, 3] = self.rest, self.head
        return m


def _basis_axis(v: np.ndarray) -> tuple[int, float] | None:
    """(index, sign) if ``v`` is a signed basis axis, else None."""
    i = int(np.argmax(np.abs(v)))
    return (i, float(np.sign(v[i]))) if abs(abs(v[i]) - 1.0) < 1e-6 else None


def joint_groups(model: Model) -> list[list[int]]:
    """Partition the joints into groups (see the module docstring); each group's joints form one chain."""
    n = model.n
    children = [[] for _ in range(n)]
    for j in range(n):
        if model.parent[j] >= 0:
            children[model.parent[j]].append(j)
    tcp_links = {t.link for t in model.tcps.values()}
    group_of = np.full(n, -1)
    groups: list[list[int]] = []
    for j in range(n):  # parents come before children (ModelBuilder order)
        p = int(model.parent[j])
        if p >= 0 and _extends(model, groups[group_of[p]], j, children, tcp_links):
            groups[group_of[p]].append(j)
            group_of[j] = group_of[p]
        else:
            groups.append([j])
            group_of[j] = len(groups) - 1
    return groups


def _extends(model: Model, group: list[int], j: int, children: list[list[int]], tcp_links: set[int]) -> bool:
    p = group[-1]
    if int(model.parent[j]) != p or len(children[p]) != 1 or p in tcp_links:
        return False
    if not np.allclose(model.origin_rotation[j], np.eye(3)):
        return False
    all_prismatic = bool(model.prismatic[group].all())
    if model.prismatic[j]:
        return all_prismatic and _basis_axis(model.axis[j]) is not None
    if not all_prismatic and np.linalg.norm(model.origin_position[j]) > _EPS:
        return False
    axis = _basis_axis(model.axis[j])
    used = [_basis_axis(model.axis[k]) for k in group if not model.prismatic[k]]
    return axis is not None and None not in used and axis[0] not in [u[0] for u in used]


class RigLayout:
    """Bones for a model, and conversions between joint values, bone channels and bone matrices."""

    def __init__(self, model: Model) -> None:
        self.model = model
        zero = model.forward(model.zero_pose())
        self.zero = zero
        groups = joint_groups(model)
        self.bone_of_link = np.zeros(model.n, dtype=int)
        for b, g in enumerate(groups):
            self.bone_of_link[g] = b
        heads = np.array([zero.position[g[-1]] for g in groups])
        masses = np.array([model.mass[g].sum() for g in groups])
        parents = [int(self.bone_of_link[model.parent[g[0]]]) if model.parent[g[0]] >= 0 else -1 for g in groups]
        subtree = masses.copy()
        for b in reversed(range(len(groups))):
            if parents[b] >= 0:
                subtree[parents[b]] += subtree[b]
        kids = [[c for c in range(len(groups)) if parents[c] == b] for b in range(len(groups))]
        self.bones: list[BoneSpec] = []
        for b, g in enumerate(groups):
            end = self._segment_end(b, g, heads, subtree, kids[b])
            self.bones.append(self._bone(b, g, parents[b], heads[b], end, masses[b]))
        self.index = {bone.name: i for i, bone in enumerate(self.bones)}

    def _segment_end(self, b: int, g: list[int], heads: np.ndarray, subtree: np.ndarray, kids: list[int]) -> np.ndarray:
        """Where the segment ends: the child joint carrying the most mass (the mean of near ties, e.g. both hips),
        else twice the way to the center of mass, else along the parent bone."""
        head = heads[b]
        away = [c for c in kids if np.linalg.norm(heads[c] - head) > MIN_LENGTH]
        if away:
            heaviest = subtree[away].max()
            main = [c for c in away if subtree[c] >= 0.9 * heaviest]
            return heads[main].mean(axis=0)
        m = self.model.mass[g]
        if m.sum() > 0:
            com = (m @ self.zero.com[g]) / m.sum()
            if np.linalg.norm(com - head) > MIN_LENGTH:
                return head + 2.0 * (com - head)
        parent = self.bones[self.bone_of_link[self.model.parent[g[0]]]] if self.model.parent[g[0]] >= 0 else None
        if parent is None:
            return head + np.array([0.0, 0.0, 0.1])
        return head + parent.rest[:, 1] * max(0.75 * parent.length, MIN_LENGTH)

    def _bone(self, b: int, g: list[int], parent: int, head: np.ndarray, end: np.ndarray, mass: float) -> BoneSpec:
        model = self.model
        link_rot = self.zero.rotation[g[-1]]
        along = link_rot.T @ (end - head)
        i = int(np.argmax(np.abs(along)))
        y = np.zeros(3)
        y[i] = 1.0 if along[i] >= 0 else -1.0
        x = np.array([1.0, 0.0, 0.0]) if i != 0 else np.array([0.0, 0.0, 1.0])
        perm = np.column_stack([x, y, np.cross(x, y)])  # bone axes in the link frame
        channels: list[Channel] = []
        letters: list[int] = []
        exact = True
        for j in g:
            mapped = _basis_axis(perm.T @ model.axis[j])
            if mapped is None:
                exact = False
                continue
            prop = "location" if model.prismatic[j] else "rotation_euler"
            channels.append(Channel(j, prop, mapped[0], mapped[1]))
            if prop == "rotation_euler":
                letters.append(mapped[0])
        if exact:
            order = letters + [k for k in range(3) if k not in letters]
            mode = "".join(LETTERS[k] for k in reversed(order))
            lock_rot = tuple(k not in letters for k in range(3))
        else:  # rotations come from the link frames; only slides stay channels
            mode, lock_rot = "QUATERNION", (False, False, False)
            channels = [c for c in channels if c.prop == "location"]
        moved = {c.index for c in channels if c.prop == "location"}
        return BoneSpec(
            name=model.link_names[g[-1]],
            parent=parent,
            joints=tuple(g),
            link=g[-1],
            head=head.copy(),
            length=max(abs(float(along[i])), MIN_LENGTH),
            rest=link_rot @ perm,
            rotation_mode=mode,
            channels=tuple(channels),
            lock_location=tuple(k not in moved for k in range(3)),
            lock_rotation=lock_rot,
            segment_end=end,
            mass=float(mass),
        )

    def bone_matrices(self, kin: Kinematics) -> np.ndarray:
        """(bones, 4, 4) pose matrices in armature space: each bone frame carried by its link."""
        out = np.zeros((len(self.bones), 4, 4))
        out[:, 3, 3] = 1.0
        for b, bone in enumerate(self.bones):
            rot0 = self.zero.rotation[bone.link]
            out[b, :3, :3] = kin.rotation[bone.link] @ rot0.T @ bone.rest
            out[b, :3, 3] = kin.position[bone.link]
        return out

    def basis_matrices(self, kin: Kinematics) -> np.ndarray:
        """(bones, 4, 4) local (matrix_basis) transforms: Blender's pose = parent_pose parent_rest^-1 rest basis."""
        pose = self.bone_matrices(kin)
        out = np.empty_like(pose)
        for b, bone in enumerate(self.bones):
            rest = bone.matrix()
            if bone.parent < 0:
                out[b] = np.linalg.solve(rest, pose[b])
            else:
                parent = self.bones[bone.parent]
                local_rest = np.linalg.solve(parent.matrix(), rest)
                local_pose = np.linalg.solve(pose[bone.parent], pose[b])
                out[b] = np.linalg.solve(local_rest, local_pose)
        return out

    def channel_values(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(bones, 3) location and (bones, 3) Euler values for joint values ``theta`` (exact bones only)."""
        loc = np.zeros((len(self.bones), 3))
        euler = np.zeros((len(self.bones), 3))
        for b, bone in enumerate(self.bones):
            for c in bone.channels:
                (loc if c.prop == "location" else euler)[b, c.index] = c.sign * theta[c.joint]
        return loc, euler

    def theta_from_channels(self, loc: np.ndarray, euler: np.ndarray, fallback: np.ndarray) -> np.ndarray:
        """Joint values read from bone channels; joints of quaternion bones keep ``fallback``."""
        theta = np.array(fallback, dtype=float)
        for b, bone in enumerate(self.bones):
            if not bone.exact:
                continue
            for c in bone.channels:
                theta[c.joint] = c.sign * (loc if c.prop == "location" else euler)[b, c.index]
        return theta

    def tcp_in_bone(self, name: str) -> tuple[int, np.ndarray]:
        """(bone index, 4x4 TCP frame in that bone's frame), constant for every pose."""
        tcp = self.model.tcp(name)
        b = int(self.bone_of_link[tcp.link])
        rot, pos = self.zero.tcp_frame(tcp)
        frame = np.eye(4)
        frame[:3, :3], frame[:3, 3] = rot, pos
        return b, np.linalg.solve(self.bones[b].matrix(), frame)
