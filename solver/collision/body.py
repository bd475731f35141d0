"""The body's collision shapes: one capsule per link that carries mass, sized from the manikin's own segment data.

A capsule runs along its segment in the zero pose: from the link's joint to the joint of the heaviest link below
it (the mean of near ties: both hips below the pelvis), or, for an end segment (head, hand), to twice the way to
its centre of mass; a link with a sole (a foot, the snake's base) lies on it instead, along the sole and no
thicker than half the sole's width, so a foot standing on the floor touches it and does not sink in. The radius
makes a cylinder of that length hold the segment's mass at the density of water (``DENSITY``; de Leva's segment
masses and Winter's lengths, see :mod:`solver.body.humans.anthropometry`, so the shapes follow the manikin's sex,
stature and body mass), kept within ``[MIN_RADIUS, MAX_RADIUS]``. A cylinder of the segment's mass is a rough
body: the trunk comes out round (its width about right, its depth too large), a limb about its mean girth.
Massless links (fingers, toes, the exterior root) get no capsule.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .. import kernels
from ..body.model import Kinematics, Model, Tcp
from ..kernels.clearance import capsule_ends

DENSITY = 1000.0  # kg/m^3, water (a body's mean density is within 10 % of it)
MIN_RADIUS = 0.01  # m
MAX_RADIUS = 0.16  # m: about half a trunk's width
MIN_LENGTH = 0.01  # m: a child joint closer than this does not end a segment


@dataclass(frozen=True)
class BodyCapsules:
    """Capsule i rides on link ``link[i]``: the segment ``start[i]``-``end[i]`` (m, in the link's frame) swept by a
    ball of radius ``radius[i]`` (m); ``names[i]`` is the link's name."""

    names: tuple[str, ...]
    link: np.ndarray  # (k,) int
    start: np.ndarray  # (k, 3) m, link frame
    end: np.ndarray  # (k, 3) m, link frame
    radius: np.ndarray  # (k,) m

    def __post_init__(self) -> None:
        # the kernel's contiguous copies, made once per capsule set
        object.__setattr__(self, "_link64", np.ascontiguousarray(self.link, dtype=np.int64))
        object.__setattr__(self, "_start", np.ascontiguousarray(self.start, dtype=float))
        object.__setattr__(self, "_end", np.ascontiguousarray(self.end, dtype=float))

    def __len__(self) -> int:
        return len(self.names)

    def world(self, kin: Kinematics) -> tuple[np.ndarray, np.ndarray]:
        """The capsules' end points in world coordinates (m), each (k, 3), for the pose ``kin``."""
        if kernels.active():
            p0, p1 = np.empty((len(self.link), 3)), np.empty((len(self.link), 3))
            capsule_ends(kin.rotation, kin.position, self._link64, self._start, self._end, p0, p1)
            return p0, p1
        rot, pos = kin.rotation[self.link], kin.position[self.link]
        return (pos + (rot @ self.start[:, :, None])[:, :, 0], pos + (rot @ self.end[:, :, None])[:, :, 0])


def body_capsules(model: Model) -> BodyCapsules:
    """One capsule per link with mass (see the module docstring)."""
    zero = model.forward(model.zero_pose())
    heavy = model.mass > 0.0
    subtree = model.descendant.astype(float) @ model.mass  # kg below (and on) each link
    names, links, starts, ends, radii = [], [], [], [], []
    soles = {tcp.link: tcp for tcp in model.tcps.values() if tcp.sole is not None}
    for j in np.flatnonzero(heavy):
        head = zero.position[j]
        end = _segment_end(model, zero, j, heavy, subtree)
        if end is None:
            continue
        length = float(np.linalg.norm(end - head))
        radius = float(np.clip(np.sqrt(model.mass[j] / (DENSITY * np.pi * length)), MIN_RADIUS, MAX_RADIUS))
        if j in soles:  # a foot (or the snake's base) lies on its sole, not along the way to its centre of mass
            start, stop, radius = _over_sole(soles[j], radius)
        else:
            start, stop = np.zeros(3), zero.rotation[j].T @ (end - head)  # zero-pose world offset, in the link frame
        names.append(model.link_names[j])
        links.append(j)
        starts.append(start)
        ends.append(stop)
        radii.append(radius)
    return BodyCapsules(
        tuple(names), np.array(links, dtype=int), np.array(starts).reshape(-1, 3), np.array(ends).reshape(-1, 3),
        np.array(radii),
    )  # fmt: skip


@lru_cache(maxsize=8)
def capsules_of(model: Model) -> BodyCapsules:
    """:func:`body_capsules` of ``model``, built once per model."""
    return body_capsules(model)


def _over_sole(tcp: Tcp, radius: float) -> tuple[np.ndarray, np.ndarray, float]:
    """(start, end, radius) of a capsule resting on ``tcp``'s sole: along the sole's longer extent, at most half
    its shorter one thick, its lowest points on the sole plane (link frame, m)."""
    sole = np.asarray(tcp.sole, dtype=float)
    low, high = sole.min(axis=0), sole.max(axis=0)
    long_axis = int(np.argmax(high - low))
    radius = min(radius, 0.5 * float((high - low)[1 - long_axis]))
    centre = 0.5 * (low + high)
    half = max(0.5 * float((high - low)[long_axis]) - radius, 0.0)
    ends = []
    for sign in (-1.0, 1.0):
        local = np.array([centre[0], centre[1], radius])
        local[long_axis] += sign * half
        ends.append(tcp.position + tcp.rotation @ local)
    return ends[0], ends[1], radius


def _segment_end(model: Model, zero: Kinematics, j: int, heavy: np.ndarray, subtree: np.ndarray):
    """Zero-pose world end of link j's segment (m), or None when it has no extent."""
    head = zero.position[j]
    below = [k for k in _heavy_children(model, j, heavy) if np.linalg.norm(zero.position[k] - head) > MIN_LENGTH]
    if below:
        most = max(subtree[k] for k in below)
        return np.mean([zero.position[k] for k in below if subtree[k] >= 0.9 * most], axis=0)
    com = zero.position[j] + zero.rotation[j] @ model.com[j]
    return head + 2.0 * (com - head) if np.linalg.norm(com - head) > MIN_LENGTH / 2 else None


def _heavy_children(model: Model, j: int, heavy: np.ndarray) -> list[int]:
    """The links with mass whose nearest ancestor with mass is j."""
    out = []
    for k in np.flatnonzero(heavy & model.descendant[j]):
        if k == j:
            continue
        p = int(model.parent[k])
        while p >= 0 and not heavy[p]:
            p = int(model.parent[p])
        if p == j:
            out.append(int(k))
    return out
