"""The typed frame: one solved pose as world-space arrays, from a :class:`~solver.Result` or a result file.

Everything the ergonomics needs and the result file holds per frame: joints (value, limits, world position and
axis, type, the link each moves, strength), links (parent, mass, world centre of mass), TCP frames, gravity,
contact wrenches and external loads. Units: m, N, N*m, kg, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from ...body.model import GRAVITY
from ...body.tree import descendants
from ...collision.body import capsules_of

if TYPE_CHECKING:
    from ...body.model import Kinematics, Model
    from ...body.state import State
    from ...iteration.result import Result


@dataclass
class Frame:
    """One frame as arrays. Joint i moves link ``joint_link[i]``; ``below[j, k]``: link k in the subtree of link j
    (itself included). A frame is a value, not changed once made: the readers give a held pose's frames the same
    arrays (read-only in a frame of a pose, :func:`frame_of_pose`), and the writers keep a held pose's text
    (:meth:`same_pose`); to change one, copy it (``dataclasses.replace`` with new arrays)."""

    number: int
    converged: bool | None
    joint_names: list[str]
    joint_value: np.ndarray  # (n,) rad or m
    joint_range: np.ndarray  # (n, 2) lower, upper limit (rad or m), +-inf if none
    joint_position: np.ndarray  # (n, 3) m, world
    joint_axis: np.ndarray  # (n, 3) unit, world
    prismatic: np.ndarray  # (n,) bool
    joint_link: np.ndarray  # (n,) int, index into links
    joint_strength: np.ndarray | None  # (n, 2) capacity [negative, positive], inf unlimited, NaN unknown
    link_names: list[str]
    link_parent: np.ndarray  # (L,) int, -1 for a root
    link_mass: np.ndarray  # (L,) kg
    link_com: np.ndarray  # (L, 3) m
    tcp_position: dict[str, np.ndarray]
    tcp_rotation: dict[str, np.ndarray]  # 3x3, world
    tcp_link: dict[str, int]
    gravity: np.ndarray
    contacts: list[tuple[str, np.ndarray, np.ndarray, np.ndarray]]  # (tcp, point, force, moment about the point)
    loads: list[tuple[str, np.ndarray, np.ndarray]]  # (tcp, point, force)
    unmet: tuple[str, ...] = ()  # constraints the solve left unmet (reach targets short, or priority 1 broken)
    broken: tuple[str, ...] = ()  # the unmet ones of priority 1 (supports, loops, balance): loads not physical
    collision_shapes: list[tuple[str, np.ndarray, np.ndarray, float]] = field(
        default_factory=list
    )  # (link, ends m, r m)
    below: np.ndarray = field(init=False)  # (L, L) bool
    below_weights: np.ndarray = field(init=False)  # (L, L) float: below as 0.0 / 1.0, for sums over subtrees
    index: dict[str, int] = field(init=False)  # joint name -> index

    def __post_init__(self) -> None:
        tree = tuple(np.asarray(self.link_parent, dtype=int).tolist())
        self.below, self.below_weights = _below(tree), _below_weights(tree)
        self.index = {n: i for i, n in enumerate(self.joint_names)}

    def joint(self, name: str) -> int | None:
        """Index of joint ``name`` or None."""
        return self.index.get(name)

    def has(self, *names: str) -> bool:
        return all(n in self.index for n in names)

    def pos(self, name: str) -> np.ndarray:
        return self.joint_position[self.index[name]]

    def value(self, name: str) -> float:
        return float(self.joint_value[self.index[name]])

    def same_pose(self, other: Frame | None) -> bool:
        """Whether ``other`` holds every field of this frame but the solve's (``number``, ``converged``, ``unmet``,
        ``broken``) bit for bit: the same body, pose, contacts and loads (a held pose)."""
        return other is not None and all(_same(getattr(self, name), getattr(other, name)) for name in _POSE_FIELDS)

    def status(self) -> str:
        """ "converged", "out of reach: ..." (priority 1 held: a real, balanced pose), "NOT held: ..." (its loads
        are not physical) or "unknown" (a file without the solve's status)."""
        if self.converged is None:
            return "unknown"
        if self.converged:
            return "converged"
        if self.broken:
            return "NOT held: " + ", ".join(self.broken)
        return "out of reach: " + ", ".join(self.unmet)


_SOLVE_FIELDS = ("number", "converged", "unmet", "broken")
_POSE_FIELDS = tuple(f.name for f in fields(Frame) if f.init and f.name not in _SOLVE_FIELDS)


def _same(a: object, b: object) -> bool:
    """``a`` and ``b`` (arrays, floats and containers of them) the same numbers: arrays bit for bit, floats by value
    and sign (0.0 is not -0.0; NaN is NaN)."""
    if a is b:
        return True
    kind = type(a)
    if kind is not type(b):
        return False
    if kind is np.ndarray:
        return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()
    if kind is dict:
        return list(a) == list(b) and all(_same(a[k], b[k]) for k in a)
    if kind is list or kind is tuple:
        return len(a) == len(b) and all(map(_same, a, b))
    if kind is float:
        return (a == b and (a != 0.0 or math.copysign(1.0, a) == math.copysign(1.0, b))) or (a != a and b != b)
    return a == b


@lru_cache(maxsize=16)
def _below(parent: tuple[int, ...]) -> np.ndarray:
    """The subtree matrix of a tree, shared read-only by every frame of a motion (it is O(L^2) to build)."""
    below = descendants(np.array(parent, dtype=int))
    below.setflags(write=False)
    return below


@lru_cache(maxsize=16)
def _below_weights(parent: tuple[int, ...]) -> np.ndarray:
    """:func:`_below` as floats, shared read-only the same way."""
    weights = _below(parent).astype(float)
    weights.setflags(write=False)
    return weights


def frame_of_result(result: Result, number: int = 1, state: State | None = None, posed: Frame | None = None) -> Frame:
    """The frame of a solve's result (what its result file would hold, without writing it); ``state`` is the
    result's state when the caller has it already; ``posed``: a frame of the same model and kinematics (the same
    object: a held pose), whose posed arrays (read, never changed) this frame takes as they are."""
    problem = result.problem
    state = result.state if state is None else state
    contacts = [(c["tcp"], c["point"], c["force"], c["moment"]) for c in result.contacts]
    loads = [(ld.tcp.name, p, ld.force) for ld, p in zip(problem.loads, state.statics.load_points, strict=True)]
    status = dict(number=number, converged=result.converged, unmet=tuple(result.unmet), broken=tuple(result.broken))
    if posed is not None:
        return replace(posed, **status, contacts=contacts, loads=loads)
    return frame_of_pose(problem.model, state.kin, status, contacts, loads)


class ResultFrames:
    """:func:`frame_of_result` of result after result (a motion's), a frame of the solver's same kinematics object as
    the frame before (a held pose: :meth:`State.adopt`) sharing that frame's posed arrays."""

    def __init__(self) -> None:
        self._last: tuple[Kinematics, Frame] | None = None  # the last frame's kinematics (the solver's) and frame

    def __call__(self, result: Result, number: int = 1, state: State | None = None) -> Frame:
        kin = (result.state if state is None else state).kin
        posed = self._last[1] if self._last is not None and self._last[0] is kin else None
        f = frame_of_result(result, number, state, posed)
        self._last = (kin, f)
        return f


def frame_of_pose(
    model: Model,
    kin: Kinematics,
    status: dict,
    contacts: list[tuple[str, np.ndarray, np.ndarray, np.ndarray]],
    loads: list[tuple[str, np.ndarray, np.ndarray]],
    gravity: np.ndarray = GRAVITY,
) -> Frame:
    """The frame of ``model`` posed as ``kin`` (its forward kinematics) with these contacts and loads; ``status``:
    the Frame's fields about the solve (``number``, ``converged``, and optionally ``unmet``, ``broken``)."""
    rotations, positions = kin.tcp_frames(list(model.tcps.values()))
    capsules = capsules_of(model)
    ends = capsules.world(kin)
    posed = dict(
        joint_value=np.array(kin.theta, dtype=float),
        joint_range=np.column_stack([model.lower, model.upper]),
        joint_position=kin.position.copy(),
        joint_axis=kin.axis.copy(),
        prismatic=model.prismatic.copy(),
        joint_link=np.arange(model.n),
        joint_strength=model.strength.copy(),
        link_parent=np.asarray(model.parent, dtype=int).copy(),
        link_mass=model.mass.copy(),
        link_com=kin.com.copy(),
        gravity=np.asarray(gravity, dtype=float).copy(),
    )
    for a in (*posed.values(), rotations, positions, *ends):  # shared by a held pose's frames: made read-only
        a.setflags(write=False)
    radii = capsules.radius.tolist()  # Python floats: float() of each numpy scalar
    shapes = [(n, a, b, r) for n, a, b, r in zip(capsules.names, *ends, radii, strict=True)]
    return Frame(
        **status,
        **posed,
        joint_names=list(model.joint_names),
        link_names=list(model.link_names),
        tcp_position=dict(zip(model.tcps, positions, strict=True)),
        tcp_rotation=dict(zip(model.tcps, rotations, strict=True)),
        tcp_link={name: tcp.link for name, tcp in model.tcps.items()},
        contacts=contacts,
        loads=loads,
        collision_shapes=shapes,
    )
