"""What a user specifies for a pose, as plain frozen values, and their validation: targets, loops, external loads,
and the whole problem as one :class:`ProblemSpec`.

Units: m, N, rad; rotations are 3x3 matrices. :func:`validate` refuses a bad specification with one ManikinError
line naming the item and what was expected.
"""

from __future__ import annotations

import dataclasses
import math
import operator
from dataclasses import dataclass, field

import numpy as np

from ..body.model import Model
from ..collision import Obstacle
from ..collision.carried import Carried
from ..comfort import DEFAULT_COMFORT, Comfort, ComfortWeights
from ..constraints import AXES, Constraint, lock_operator
from ..errors import ManikinError
from ..options import MAX_WEIGHT, MIN_WEIGHT

HARD, SOFT = 1, 2  # priority levels: what must hold, and what is met as closely as it can be
PRIORITIES = (HARD, SOFT)


def default_priority(support: bool) -> int:
    """A support holds the body up (hard); any other target is a reach target (soft)."""
    return HARD if support else SOFT


@dataclass(frozen=True)
class Target:
    """Hold ``tcp`` on a world frame. ``rotation`` (3x3) None means the TCP's zero-pose orientation.

    ``lock`` lists the constrained axes of the target frame; ``operator`` (k x 6) replaces it when given.
    A ``support`` target also carries contact forces (friction coefficient ``friction``, optional sole).
    ``priority`` 1 must hold, 2 is met as closely as it can be (:mod:`solver.problem.priorities`); None: 1 for a
    support, 2 otherwise.
    """

    tcp: str
    position: np.ndarray
    rotation: np.ndarray | None = None
    lock: tuple[str, ...] = AXES
    operator: np.ndarray | None = None
    weight: float = 1.0
    support: bool = False
    friction: float = 0.6
    sole: np.ndarray | None = None
    enabled: bool = True
    priority: int | None = None

    @property
    def effective_priority(self) -> int:
        """1 (must hold) or 2 (reach: as close as possible)."""
        return self.priority if self.priority is not None else default_priority(self.support)

    def at(self, position: np.ndarray, rotation: np.ndarray | None) -> Target:
        """This target moved to another frame (``position`` m, ``rotation`` 3x3 or None): what
        ``dataclasses.replace(self, position=..., rotation=...)`` gives, without its __init__ (a keyed target at each
        frame of a motion; Target has no __post_init__ to run)."""
        moved = object.__new__(type(self))
        moved.__dict__.update(self.__dict__, position=position, rotation=rotation)
        return moved


@dataclass(frozen=True)
class Loop:
    """Hold ``tcp`` on the frame of ``other`` composed with an offset (in ``other``'s frame)."""

    tcp: str
    other: str
    offset_position: np.ndarray = field(default_factory=lambda: np.zeros(3))
    offset_rotation: np.ndarray | None = None
    lock: tuple[str, ...] = ("x", "y", "z")
    operator: np.ndarray | None = None
    weight: float = 1.0


@dataclass(frozen=True)
class ExternalLoad:
    """A force (N, world frame) applied at ``tcp``."""

    tcp: str
    force: np.ndarray


@dataclass(frozen=True, eq=False)
class ProblemSpec:
    """What a problem is made of, one value (:class:`~solver.problem.problem.Problem` builds its rows from it and a
    model). Sequences are kept as tuples; :meth:`replace` makes another.

    ``targets``, ``loops``, ``loads``: the frames to reach and hold and the forces applied (m, N). ``balance``: static
    balance with contact forces at the supports. ``comfort_weights``: the standard comfort terms' weights, unless
    ``comfort`` (a :class:`~solver.comfort.Comfort`) replaces the terms. ``reduction``: the variable groups
    (:mod:`solver.body.reduction`). ``extra_constraints``: any :class:`~solver.constraints.Constraint`, ranked with
    balance. ``floor``: every body part above z = 0. ``obstacles``: shapes the body keeps its clearance from.
    ``self_collision``: hands and forearms out of the trunk, head and thighs, the shanks apart. ``carried``: a box
    held between two TCPs, kept out of the body, the obstacles and the floor.
    """

    targets: tuple[Target, ...] = ()
    loops: tuple[Loop, ...] = ()
    loads: tuple[ExternalLoad, ...] = ()
    balance: bool = True
    comfort_weights: ComfortWeights = DEFAULT_COMFORT
    reduction: tuple[str, ...] = ()
    extra_constraints: tuple[Constraint, ...] = ()
    comfort: Comfort | None = None
    floor: bool = True
    obstacles: tuple[Obstacle, ...] = ()
    self_collision: bool = True
    carried: Carried | None = None

    def __post_init__(self) -> None:
        for name in _SEQUENCES:
            object.__setattr__(self, name, tuple(getattr(self, name)))

    def replace(self, **changes) -> ProblemSpec:
        """This spec with ``changes`` (fields by name): what ``dataclasses.replace`` gives, the fields not changed
        shared instead of passed through __init__ again (a motion's every frame changes its targets)."""
        if not changes.keys() <= _SPEC_FIELDS:
            return dataclasses.replace(self, **changes)  # raises, naming the unknown field
        out = object.__new__(type(self))
        out.__dict__.update(self.__dict__)
        for name, value in changes.items():
            object.__setattr__(out, name, tuple(value) if name in _SEQUENCES else value)
        return out

    @property
    def weights(self) -> ComfortWeights | None:
        """The standard comfort terms' weights this spec's comfort has (None: its own terms, not the standard)."""
        return self.comfort_weights if self.comfort is None else self.comfort.weights


_SEQUENCES = ("targets", "loops", "loads", "reduction", "extra_constraints", "obstacles")  # kept as tuples
_SPEC_FIELDS = frozenset(f.name for f in dataclasses.fields(ProblemSpec))

MAX_DISTANCE = 1000.0  # m: targets and offsets farther than this from the origin are refused
MAX_FORCE = 1e6  # N


_EYE3 = np.eye(3)  # orthonormality within np.allclose(atol=1e-6) of it: the check without its overhead


def _check_vector(what: str, value, size: int, limit: float) -> np.ndarray:
    v = np.asarray(value, dtype=float)
    if v.shape != (size,) or not np.isfinite(v).all():
        raise ManikinError(f"{what}: expected {size} finite numbers, got {value!r}")
    if np.abs(v).max(initial=0.0) > limit:
        raise ManikinError(f"{what}: expected values within +-{limit:g}, got {value!r}")
    return v


def _finite(value) -> bool:
    """np.isfinite of a number, in Python for a float."""
    return math.isfinite(value) if type(value) is float else bool(np.isfinite(value))


def _check_rotation(what: str, value) -> None:
    if value is None:
        return
    r = np.asarray(value, dtype=float)
    ok = r.shape == (3, 3) and np.isfinite(r).all()
    if not ok or (np.abs(r.T @ r - _EYE3) > 1e-6 + 1e-5 * _EYE3).any() or _determinant(r.tolist()) < 0:
        raise ManikinError(f"{what}: expected a rotation matrix (orthonormal, det +1)")


def _determinant(r: list[list[float]]) -> float:
    """det of a 3x3 matrix given as rows (its sign is certain here: the matrix is orthonormal, det +-1)."""
    (a, b, c), (d, e, f), (g, h, i) = r
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)


def _check_relaxation(what: str, lock, operator) -> None:
    if operator is None:
        lock_operator(lock)  # raises on unknown axes
        if not lock:
            raise ManikinError(f"{what}: lock must name at least one axis")
        return
    op = np.asarray(operator, dtype=float)
    if op.ndim != 2 or op.shape[1] != 6 or op.shape[0] == 0 or not np.isfinite(op).all():
        raise ManikinError(f"{what}: operator must be k x 6 finite numbers")
    if not (np.abs(op).max(axis=1) >= 1e-6).all():
        raise ManikinError(f"{what}: operator rows must not be zero (largest |entry| >= 1e-06)")


def _check_frame(what: str, position, rotation, lock, operator, weight: float) -> None:
    if not _fine_position(position):  # only then the check that says why (a run of a study: ~10 us less a target)
        _check_vector(f"{what} position", position, 3, MAX_DISTANCE)
    if not _fine_rotation(rotation):
        _check_rotation(f"{what} rotation", rotation)
    _check_relaxation(what, lock, operator)
    if not (_finite(weight) and MIN_WEIGHT <= weight <= MAX_WEIGHT):
        raise ManikinError(f"{what}: weight must be a number in [{MIN_WEIGHT:g}, {MAX_WEIGHT:g}], got {weight!r}")


def same_supports(enabled: list[Target], targets: list[Target]) -> bool:
    """Whether ``targets``' enabled supports are those of ``enabled`` (TCP, rotation, friction and sole alike)."""

    def key(t: Target) -> tuple:
        rot = None if t.rotation is None else np.asarray(t.rotation).tobytes()
        sole = None if t.sole is None else np.asarray(t.sole).tobytes()
        return (t.tcp, rot, t.friction, sole)

    old = [t for t in enabled if t.support]
    new = [t for t in targets if t.enabled and t.support]
    if len(old) == len(new) and all(map(operator.is_, old, new)):
        return True  # the very same supports (a motion's unkeyed feet): their keys are equal (friction is not NaN)
    return [key(t) for t in old] == [key(t) for t in new]


_KEPT = operator.attrgetter("tcp", "lock", "weight", "support", "friction", "enabled", "priority")


def same_but_frames(old: Target, new: Target) -> bool:
    """Whether ``new`` is ``old`` with another position or rotation only (None stays None): a keyed target's move."""
    if old is new:
        return True
    if (old.rotation is None) != (new.rotation is None) or _KEPT(old) != _KEPT(new):  # (validated: no NaN weight)
        return False
    return all(a is b or (a is not None and b is not None and np.array_equal(a, b))
               for a, b in ((old.operator, new.operator), (old.sole, new.sole)))  # fmt: skip


def same_frame(a: Target, b: Target) -> bool:
    """Whether targets ``a`` and ``b`` hold their TCPs at the very same frame: the same object, or equal positions
    and rotations (a target read again from a scene that did not move it, as a bake reads every frame)."""
    if a is b:
        return True
    if (a.rotation is None) != (b.rotation is None) or not _equal(a.position, b.position):
        return False
    return a.rotation is None or _equal(a.rotation, b.rotation)


def _equal(a: object, b: object) -> bool:
    """``np.array_equal(a, b)`` (-0.0 equals 0.0, a NaN nothing); two float64 arrays of one shape by their lists of
    new Python floats, without its calls (a motion asks it of every target every frame)."""
    if type(a) is np.ndarray and type(b) is np.ndarray and a.shape == b.shape and a.dtype == b.dtype == np.float64:
        return a.tolist() == b.tolist()
    return bool(np.array_equal(a, b))


def validate_frames(targets, checked=()) -> None:
    """:func:`validate` of the positions and rotations alone (the rest of each target checked before). A target at
    the frame of the one at its index in ``checked`` (the targets of a problem, validated then) is not checked
    again."""
    for i, t in enumerate(targets):
        if i < len(checked) and same_frame(t, checked[i]):
            continue
        if not (_fine_position(t.position) and _fine_rotation(t.rotation)):  # only then the checks that say why
            _check_vector(f"target {t.tcp} position", t.position, 3, MAX_DISTANCE)
            _check_rotation(f"target {t.tcp} rotation", t.rotation)


def _fine_position(value) -> bool:
    """Whether ``value`` is surely a target position :func:`_check_vector` accepts (False: ask it), in Python floats:
    a float64 3-vector within +-MAX_DISTANCE (a NaN fails every comparison)."""
    if type(value) is not np.ndarray or value.dtype != np.float64 or value.shape != (3,):
        return False
    (x, y, z), low, high = value.tolist(), -MAX_DISTANCE, MAX_DISTANCE
    return low <= x <= high and low <= y <= high and low <= z <= high


def _fine_rotation(value) -> bool:
    """Whether ``value`` is surely a rotation :func:`_check_rotation` accepts (False: ask it), in Python floats: R^T R
    within its tolerances less 1e-9 (far more than R^T R's rounding, however it is summed), det >= 0."""
    if value is None:
        return True
    if type(value) is not np.ndarray or value.dtype != np.float64 or value.shape != (3, 3):
        return False
    rows = value.tolist()
    (a, b, c), (d, e, f), (g, h, i) = rows
    diagonal, off = 1.1e-5 - 1e-9, 1e-6 - 1e-9
    return (abs(a * a + d * d + g * g - 1.0) <= diagonal and abs(b * b + e * e + h * h - 1.0) <= diagonal
            and abs(c * c + f * f + i * i - 1.0) <= diagonal and abs(a * b + d * e + g * h) <= off
            and abs(a * c + d * f + g * i) <= off and abs(b * c + e * f + h * i) <= off
            and _determinant(rows) >= 0)  # fmt: skip


def validate(model: Model, targets, loops, loads) -> None:
    """Refuse bad specifications with a ManikinError that names the item and what was expected."""
    for t in targets:
        what = f"target {t.tcp}"
        model.tcp(t.tcp)
        _check_frame(what, t.position, t.rotation, t.lock, t.operator, t.weight)
        if t.priority is not None and t.priority not in PRIORITIES:
            expected = "1 (must hold) or 2 (as close as possible)"
            raise ManikinError(f"{what}: priority must be {expected}, got {t.priority!r}")
        if not (_finite(t.friction) and t.friction >= 0):
            raise ManikinError(f"{what}: friction must be a non-negative number")
        if t.sole is not None:
            sole = np.asarray(t.sole, dtype=float)
            if sole.ndim != 2 or sole.shape[1] != 2 or not np.isfinite(sole).all() or np.abs(sole).max() > 10:
                raise ManikinError(f"{what}: sole must be a list of finite [x, y] corners (m)")
    for lp in loops:
        what = f"loop {lp.tcp}-{lp.other}"
        model.tcp(lp.tcp)
        model.tcp(lp.other)
        _check_frame(what, lp.offset_position, lp.offset_rotation, lp.lock, lp.operator, lp.weight)
    for ld in loads:
        model.tcp(ld.tcp)
        _check_vector(f"load at {ld.tcp} force", ld.force, 3, MAX_FORCE)
