"""The manikin as a tree of 1-DoF joints: its data, forward kinematics and Jacobians (built by :mod:`.builder`).

Link i is moved by joint i; its frame sits at the joint. ``parent[i]`` is the parent link (-1 = world).
In the zero pose every link frame is a pure translation of its parent by ``origin_position`` rotated by
``origin_rotation``. Units: m, rad, kg. Forward kinematics is vectorised: zero-offset chains (a vertebra's
three rotations) are composed first, then the chains by pointer jumping (ceil(log2(depth)) batched compositions).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from .. import kernels
from ..errors import ModelError
from ..kernels.forward import link_frames
from ..kernels.frames import point_jacobian_rows
from ..kernels.statics import twists
from .spatial import cross, skew
from .tree import TreeSums, descendants

GRAVITY = np.array([0.0, 0.0, -9.81])  # m/s^2, world frame
EXTERIOR_JOINTS = ("root_tx", "root_ty", "root_tz", "root_rz", "root_rx", "root_ry")


@dataclass(frozen=True)
class Tcp:
    """A named frame on a link: ``rotation`` (3x3) and ``position`` (m) in the link frame.

    ``sole`` is an optional contact polygon (k x 2, m) in the TCP's x-y plane, used when the TCP is a support.
    """

    name: str
    link: int
    rotation: np.ndarray
    position: np.ndarray
    sole: np.ndarray | None = None


@dataclass(frozen=True, eq=False)
class Model:
    """Arrays describing the joint tree. Build with :class:`ModelBuilder`."""

    name: str
    joint_names: tuple[str, ...]
    link_names: tuple[str, ...]
    parent: np.ndarray  # (n,) int, parent link, -1 = world
    prismatic: np.ndarray  # (n,) bool
    axis: np.ndarray  # (n, 3) unit axis in the link frame
    origin_rotation: np.ndarray  # (n, 3, 3)
    origin_position: np.ndarray  # (n, 3) m, in the parent frame
    lower: np.ndarray  # (n,) rad or m
    upper: np.ndarray  # (n,)
    neutral: np.ndarray  # (n,) most comfortable value
    strength: np.ndarray  # (n, 2) N*m (N for prismatic): muscle capacity for negative, positive moments
    range_weight: np.ndarray  # (n,) weight of the joint in the comfort's joint-range term (0 = ignored)
    mass: np.ndarray  # (n,) kg of link i
    com: np.ndarray  # (n, 3) m, link i's center of mass in its frame
    tcps: dict[str, Tcp]
    info: dict = field(default_factory=dict)  # body description (sex, stature, mass, sources)
    descendant: np.ndarray = field(init=False)  # (n, n) bool, [j, k]: k in the subtree of j (self included)
    tree_sums: TreeSums = field(init=False)  # O(n) sums over every link's subtree or ancestors
    _fk: _ForwardTables = field(init=False)
    prismatic_links: np.ndarray = field(init=False)  # (p,) int, the links of the prismatic joints

    def __post_init__(self) -> None:
        object.__setattr__(self, "prismatic_links", np.flatnonzero(self.prismatic))
        object.__setattr__(self, "descendant", descendants(self.parent))
        object.__setattr__(self, "tree_sums", TreeSums(self.parent))
        object.__setattr__(self, "_fk", _ForwardTables.build(self))
        self.prismatic.setflags(write=False)
        self.descendant.setflags(write=False)

    @property
    def n(self) -> int:
        """Number of joints (= links)."""
        return len(self.joint_names)

    @property
    def total_mass(self) -> float:
        """Body mass, kg."""
        return float(self.mass.sum())

    def joint_index(self, name: str) -> int:
        try:
            return self.joint_names.index(name)
        except ValueError:
            raise ModelError(f"unknown joint '{name}'") from None

    def link_index(self, name: str) -> int:
        try:
            return self.link_names.index(name)
        except ValueError:
            raise ModelError(f"unknown link '{name}'") from None

    def tcp(self, name: str) -> Tcp:
        try:
            return self.tcps[name]
        except KeyError:
            known = ", ".join(sorted(self.tcps))
            raise ModelError(f"unknown TCP '{name}' (known: {known})") from None

    def zero_pose(self) -> np.ndarray:
        """All joint values zero (standing upright), clipped into the joint ranges."""
        return np.clip(np.zeros(self.n), self.lower, self.upper)

    def forward(self, theta: np.ndarray) -> Kinematics:
        """World frames of all links for joint values ``theta`` (rad / m)."""
        theta = np.asarray(theta, dtype=float)
        fk = self._fk
        n = len(theta)
        if kernels.active():
            rot, pos, axis, com = np.empty((n, 3, 3)), np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3))
            link_frames(theta, *fk.loop_tables, rot, pos, axis, com)
            return Kinematics(self, theta, rot, pos, axis, com)
        angle = theta[fk.store]  # links in the storage order of the chain steps
        rev_angles = np.where(fk.prismatic, 0.0, angle)
        sin, cos = np.sin(rev_angles)[:, None], np.cos(rev_angles)[:, None]
        frames = np.zeros((n, 4, 4))  # link frames in the parent link frame, then in the world
        frames[:, 3, 3] = 1.0
        spin = (fk.eye + sin * fk.axis_skew + (1.0 - cos) * fk.axis_skew2).reshape(n, 3, 3)
        slide = np.where(fk.prismatic, angle, 0.0)[:, None] * fk.axis
        if fk.origin_rotation is None:
            frames[:, :3, :3] = spin
            frames[:, :3, 3] = fk.origin_position + slide
        else:
            frames[:, :3, :3] = fk.origin_rotation @ spin
            frames[:, :3, 3] = fk.origin_position + np.einsum("nij,nj->ni", fk.origin_rotation, slide)
        # Each chain's links in the frame of the link above its head, one chain position at a time.
        for above, links in fk.chain_steps:
            frames[links] = frames[above] @ frames[links]
        # Pointer jumping over the chains in depth order (in place is safe: the right side gathers copies first).
        world = frames.take(fk.chain_end, axis=0)
        for start, anc in fk.jumps:
            world[start:] = world.take(anc, axis=0) @ world[start:]
        # the links inside a chain hang from the world frame of the chain above (the identity for a root chain)
        world_above = np.concatenate([world, fk.identity])
        for links, chain_above in fk.inner:
            frames[links] = world_above.take(chain_above, axis=0) @ frames[links]
        frames[fk.chain_end] = world
        frames = frames.take(fk.link_place, axis=0)
        axis_and_com = frames @ fk.axis_and_com  # (n, 4, 2): the joint axis (direction) and the link's COM (point)
        rot, pos = frames[:, :3, :3], frames[:, :3, 3]
        return Kinematics(self, theta, rot, pos, axis_and_com[:, :3, 0], axis_and_com[:, :3, 1])


@dataclass(frozen=True, eq=False)
class _ForwardTables:
    """Constants of :meth:`Model.forward`.

    Forward kinematics composes chains first: a link whose joint sits at its parent's (zero offset) and is
    its parent's only child joins the parent's chain (a vertebra's three rotations, the root's three slides),
    so the 160 links form ~75 chains of 1..3 links. The links are stored by chain position (all heads, then
    all second links, ...) with the chains longest first, so that composing every chain's next link with its
    predecessor is one batched product of two slices (``chain_steps``). Then the chains' end frames are
    composed by pointer jumping over the chain tree in depth order (``jumps``: in each round every chain
    whose ancestor pointer is still inside the tree composes with it; those chains form a suffix of the depth
    order, so each round updates one contiguous slice), and last the links inside a chain take the world
    frame of the chain above. About half the 4x4 products of pointer jumping over the links themselves.
    """

    store: np.ndarray  # (n,) link at each storage place
    link_place: np.ndarray  # (n,) storage place of each link
    prismatic: np.ndarray  # (n,) bool, in storage order (as are the four below)
    axis_skew: np.ndarray  # (n, 9) [axis]x, row-major
    axis_skew2: np.ndarray  # (n, 9) [axis]x^2
    axis: np.ndarray  # (n, 3) joint axis in the link frame
    origin_position: np.ndarray  # (n, 3) m, in the parent frame
    origin_rotation: np.ndarray | None  # (n, 3, 3); None when every origin rotation is the identity
    chain_steps: tuple  # ((slice of predecessors, slice of links), ...) for chain positions 1, 2, ...
    chain_end: np.ndarray  # (c,) storage place of each chain's last link, chains in depth order
    jumps: tuple  # ((start, ancestor chain of chains start:), ...)
    inner: tuple  # ((slice of links inside chains, depth-order index of the chain above each, c = none), ...)
    axis_and_com: np.ndarray  # (n, 4, 2) per link (link order): [axis, 0] and [COM, 1] in the link frame
    loop_tables: tuple  # the compiled kernel's: links parents first, then the model's arrays (contiguous float64)
    eye: np.ndarray = field(default_factory=lambda: np.eye(3).ravel())  # (9,) the identity, row-major
    identity: np.ndarray = field(default_factory=lambda: np.eye(4)[None])  # (1, 4, 4)

    @staticmethod
    def build(model: Model) -> _ForwardTables:
        parent, n = model.parent, len(model.parent)
        children = np.bincount(parent[parent >= 0], minlength=n)
        at_parent = ~np.any(model.origin_position != 0.0, axis=1) & np.all(
            model.origin_rotation == np.eye(3), axis=(1, 2)
        )
        depth = np.zeros(n, dtype=int)
        for j in _parents_first(parent):
            depth[j] = 0 if parent[j] < 0 else depth[parent[j]] + 1
        members: dict[int, list[int]] = {}  # chain head -> its links, head first
        head = np.arange(n)
        for j in np.argsort(depth, kind="stable"):
            p = parent[j]
            if p >= 0 and at_parent[j] and children[p] == 1:
                head[j] = head[p]
            members.setdefault(int(head[j]), []).append(int(j))
        heads = sorted(members, key=lambda h: (-len(members[h]), depth[h]))  # longest chains first
        chain_of = {h: c for c, h in enumerate(heads)}
        above = np.array([chain_of[int(head[parent[h]])] if parent[h] >= 0 else -1 for h in heads], dtype=int)
        chain_depth = np.zeros(len(heads), dtype=int)
        for c in np.argsort(depth[heads], kind="stable"):
            chain_depth[c] = 0 if above[c] < 0 else chain_depth[above[c]] + 1
        order = np.argsort(chain_depth, kind="stable")  # chains in depth order
        rank = np.argsort(order)
        # storage: position 0 of every chain, then position 1 of the chains that have one, ...
        longest = len(members[heads[0]]) if heads else 0
        blocks = [[members[h][k] for h in heads if len(members[h]) > k] for k in range(longest)]
        starts = np.cumsum([0] + [len(b) for b in blocks])
        store = np.array([j for b in blocks for j in b], dtype=int)
        place = np.argsort(store)
        steps = tuple(
            (slice(int(starts[k - 1]), int(starts[k - 1]) + len(blocks[k])), slice(int(starts[k]), int(starts[k + 1])))
            for k in range(1, longest)
        )
        inner = []
        for k in range(longest - 1):
            count = len(blocks[k + 1])  # chains longer than k + 1: their link k is inside the chain
            chain_above = np.where(above[:count] >= 0, rank[above[:count]], len(heads))
            inner.append((slice(int(starts[k]), int(starts[k]) + count), chain_above))
        ends = np.array([place[members[h][-1]] for h in heads], dtype=int)
        anc = np.array([rank[above[c]] if above[c] >= 0 else -1 for c in order], dtype=int)
        jumps = []
        while np.any(anc >= 0):
            start = int(np.argmax(anc >= 0))
            jumps.append((start, anc[start:].copy()))
            tail = anc[start:]
            anc[start:] = np.where(anc[tail] >= 0, anc[tail], -1)
        k = skew(model.axis)[store]
        plain = bool(np.allclose(model.origin_rotation, np.eye(3)))
        return _ForwardTables(
            store=store,
            link_place=place,
            prismatic=model.prismatic[store],
            axis_skew=k.reshape(-1, 9),
            axis_skew2=(k @ k).reshape(-1, 9),
            axis=model.axis[store],
            origin_position=model.origin_position[store],
            origin_rotation=None if plain else model.origin_rotation[store],
            chain_steps=steps,
            chain_end=ends[order],
            jumps=tuple(jumps),
            inner=tuple(inner),
            axis_and_com=np.stack(
                [np.column_stack([model.axis, np.zeros(n)]), np.column_stack([model.com, np.ones(n)])], axis=2
            ),
            loop_tables=(
                np.array(_parents_first(parent), dtype=np.int64),
                np.ascontiguousarray(parent, dtype=np.int64),
                np.ascontiguousarray(model.prismatic, dtype=np.bool_),
                *(np.ascontiguousarray(a, dtype=float) for a in (model.axis, model.origin_rotation)),
                *(np.ascontiguousarray(a, dtype=float) for a in (model.origin_position, model.com)),
            ),
        )


def _parents_first(parent: np.ndarray) -> list[int]:
    """Link indices ordered so that every link comes after its parent."""
    done = np.zeros(len(parent), dtype=bool)
    out: list[int] = []
    for j in range(len(parent)):
        stack = []
        k = j
        while k >= 0 and not done[k]:
            stack.append(k)
            k = int(parent[k])
        for k in reversed(stack):
            done[k] = True
            out.append(k)
    return out


@dataclass(frozen=True, eq=False)
class Kinematics:
    """World frames of every link for one joint vector: rotation (n,3,3), position (n,3) m, axis (n,3), com (n,3)."""

    model: Model
    theta: np.ndarray
    rotation: np.ndarray
    position: np.ndarray
    axis: np.ndarray
    com: np.ndarray

    def tcp_frame(self, tcp: Tcp) -> tuple[np.ndarray, np.ndarray]:
        """(rotation 3x3, position m) of a TCP in the world."""
        r = self.rotation[tcp.link]
        return r @ tcp.rotation, self.position[tcp.link] + r @ tcp.position

    def tcp_frames(self, tcps: list[Tcp]) -> tuple[np.ndarray, np.ndarray]:
        """(rotations (k, 3, 3), positions (k, 3) m) of TCPs in the world: :meth:`tcp_frame` of each in one go (the
        same numbers: matmul multiplies each matrix of a stack as it multiplies a single one)."""
        if not tcps:
            return np.zeros((0, 3, 3)), np.zeros((0, 3))
        links = [t.link for t in tcps]
        r = self.rotation[links]
        local = np.array([t.rotation for t in tcps], dtype=float), np.array([t.position for t in tcps], dtype=float)
        return r @ local[0], self.position[links] + (r @ local[1][:, :, None])[:, :, 0]

    def body_com(self) -> np.ndarray:
        """Whole-body center of mass, m."""
        m = self.model.mass
        return (m @ self.com) / m.sum()

    @cached_property
    def twist(self) -> np.ndarray:
        """(n, 6) per joint, for a unit joint rate: velocity of the point at the world origin moving with the
        joint's link (m/s), then angular velocity (rad/s). A point q moves with spin x q + origin; the twist
        dotted with a wrench [force, moment about the world origin] is the joint's load about its axis."""
        if kernels.active():  # both in one loop; the origin velocity kept for its own property
            out, origin = np.empty((len(self.axis), 6)), np.empty((len(self.axis), 3))
            twists(self.position, self.axis, self.model._fk.loop_tables[2], out, origin)
            self.__dict__.setdefault("origin_velocity", origin)
            return out
        out = np.empty((len(self.axis), 6))  # filled, then the few prismatic rows fixed: fewer calls than np.where
        out[:, :3] = self.origin_velocity
        out[:, 3:] = self.axis
        prismatic = self.model.prismatic_links
        if len(prismatic):
            out[prismatic, :3] = self.axis[prismatic]
            out[prismatic, 3:] = 0.0
        return out

    @property
    def twist_basis(self) -> tuple[np.ndarray, np.ndarray]:
        """(spin, origin) of :attr:`twist`, each (n, 3)."""
        return self.twist[:, 3:], self.twist[:, :3]

    @cached_property
    def origin_velocity(self) -> np.ndarray:
        """(n, 3) p x a: velocity (m/s) of the point at the world origin turning with each revolute joint."""
        if kernels.active() and "twist" not in self.__dict__:
            self.twist  # noqa: B018 (the kernel fills both)
            return self.__dict__["origin_velocity"]
        return cross(self.position, self.axis)

    def jacobian_rows(self, points: np.ndarray, rows_lin: np.ndarray, rows_ang: np.ndarray, mask) -> np.ndarray:
        """(k, n): row r is rows_lin[r] @ (d p_r / d theta) + rows_ang[r] @ (angular velocity / d theta) for a point
        p_r = ``points[r]`` (or one point (3,) for all rows), times ``mask`` ((k, n) or (n,): 1 for the joints that
        move the point's link, 0 otherwise). ``rows_lin``, ``rows_ang``: (k, 3)."""
        if kernels.active():
            n = self.model.n
            out = np.empty((len(rows_lin), n))
            points, mask = np.reshape(points, (-1, 3)), np.reshape(mask, (-1, n))
            flat = (np.ascontiguousarray(a, dtype=float) for a in (points, rows_lin, rows_ang, mask))
            point_jacobian_rows(*flat, self.twist, out)
            return out
        spin, origin = self.twist_basis
        # velocity of a point p: spin x p + origin, so l.v + m.omega = (m - l x p).spin + l.origin
        through_spin = rows_ang - cross(rows_lin, points)
        return (through_spin @ spin.T + rows_lin @ origin.T) * mask

    def frame_jacobian(self, link: int, point: np.ndarray) -> np.ndarray:
        """(6, n) geometric Jacobian [linear velocity of ``point``; angular velocity] of a frame on ``link``."""
        eye, zero = np.eye(3), np.zeros((3, 3))
        return self.jacobian_rows(point, np.vstack([eye, zero]), np.vstack([zero, eye]), self.model.descendant[:, link])
