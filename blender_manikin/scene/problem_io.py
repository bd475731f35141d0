"""Scene <-> solver: the empties of a manikin into a solver Problem, a Result back into the armature (bpy).

Everything is expressed in the armature object's space, so a manikin may stand anywhere on the floor and face
any direction; the armature must stay upright and unscaled (gravity is its -z).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import bpy
import numpy as np
from mathutils import Matrix

from ... import solver
from ...solver import ExternalLoad, Loop, ManikinError, Problem, Result, SolverOptions, Target, kernels
from ...solver.body.contacts import support_polygon
from ...solver.body.reduction import DEFAULT_GROUPS
from ...solver.collision.body import capsules_of
from ...solver.constraints.clearance import TOLERANCE
from ...solver.ergonomics import ErgoOptions
from ...solver.ergonomics.loads import percent_of_strength
from ...solver.ergonomics.registry import verdicts
from ...solver.iteration.result import shortfall_text
from ...solver.stance import FEET, bounds_of, stepping, steps_of
from .armature import color_bones_by_load, model_of, read_x, write_pose
from .carried_object import carried_spec, find_carried, follow_solve
from .obstacles import obstacle_sources, scene_obstacles
from .registries import comfort_settings, comfort_weights
from .schema import ERROR_KEY, RESULT_KEY, linked_objects, members
from .supports import STEP, floor_notes, moved_supports, pushed_notes, solved_lock

if TYPE_CHECKING:
    from ...solver.body.model import Model
    from ...solver.body.state import State
    from ...solver.collision.carried import Carried
    from ...solver.comfort.standard import ComfortWeights

TOP_LOADS = 5


def _frame(m: Matrix) -> tuple[np.ndarray, np.ndarray]:
    """(rotation 3x3, position) of a matrix, scale removed."""
    loc, quat, _scale = m.decompose()
    return np.array(quat.to_matrix()), np.array(loc)


_UP, _EYE3 = np.array([0.0, 0.0, 1.0]), np.eye(3)


def _close(a: np.ndarray, b: np.ndarray) -> bool:
    """``np.allclose(a, b, atol=1e-6)`` of finite arrays (NaN: False), without its overhead (read every frame)."""
    return bool((np.abs(a - b) <= 1e-6 + 1e-5 * np.abs(b)).all())


def _check_upright(arm: bpy.types.Object, rot: np.ndarray) -> None:
    """ManikinError unless ``rot`` (the armature's world rotation) keeps it upright and unscaled."""
    if not _close(rot[:, 2], _UP) or not _close(rot.T @ rot, _EYE3):
        raise ManikinError(f"{arm.name}: the armature must stay upright and unscaled (turn it about z only)")


@dataclass(frozen=True)
class Inputs:
    """What a problem was read from: names and flags, and the numbers (frames, offsets, forces) in armature space."""

    labels: str
    numbers: np.ndarray

    def same_as(self, other: Inputs | None, tolerance: float = 1e-5) -> bool:
        """Equal up to single-precision noise (Blender stores matrices as 32-bit floats)."""
        return (
            other is not None
            and self.labels == other.labels
            and self.numbers.shape == other.numbers.shape
            and bool(np.allclose(self.numbers, other.numbers, rtol=0.0, atol=tolerance))
        )


@dataclass
class SceneProblem:
    """A problem read from the scene, its warm start (full x: joints, forces if they fit) and options, and the
    inputs it came from."""

    problem: Problem
    x0: np.ndarray | None
    options: SolverOptions
    inputs: Inputs
    setup: tuple = ()  # everything read but the targets' poses: the same setup can share the problem's parts


def _same(a: object, b: object) -> bool:
    """The same object, or equal texts (an enum setting is read as a new str each time)."""
    return a is b or (type(a) is str and a == b)


class Held:
    """What a bake reads of the scene once and keeps through its frames (nobody edits the scene then, but anything
    may be animated): the model, the objects pointing at the armature (sorted; their roles and settings are read
    every frame), the carried box (a text property, never animated), the comfort settings (their values are read
    every frame) and the objects that may be obstacles (:class:`.obstacles.Source`: each frame reads their settings
    and matrices, and their meshes unless nothing can change them). Solve Pose and live read a new one each time."""

    def __init__(self, arm: bpy.types.Object) -> None:
        self.model = model_of(arm)
        self.linked = linked_objects(arm)
        self.carried = carried = _carried(arm, self.model)
        self.box = None if carried is None else (carried.name, carried.tcps, tuple(carried.size))
        self.sources = obstacle_sources(bpy.context.scene)
        self.comfort = comfort_settings()
        self._weights: tuple[tuple, ComfortWeights] | None = None  # the last settings' values and their weights
        self.upright = b""  # the armature's rotation last checked upright (it may be animated)
        self._targets: dict[str, tuple[tuple, Target]] = {}  # by empty: the last Target read and what it came from
        self._options: tuple[tuple, SolverOptions] | None = None  # the last options and the settings they came from
        self._text: tuple[tuple, str] | None = None  # the last settings' labels and their text

    def weights(self, settings: object) -> ComfortWeights:
        """The comfort weights ``settings`` hold now (made again when a value changed: they may be keyed)."""
        values = tuple(getattr(settings, s.prop, s.default) for s in self.comfort)
        if self._weights is None or self._weights[0] != values:
            self._weights = values, comfort_weights(settings, self.comfort)
        return self._weights[1]

    def options(self, settings: object, live: bool) -> SolverOptions:
        """The solver options the manikin's settings ask for (``live``: a drag's), the last ones while unchanged."""
        values = (settings.live_iterations if live else settings.max_iterations, settings.comfort,
                  0 if live else settings.restarts)  # a live drag keeps the arm configuration it has  # fmt: skip
        if self._options is None or self._options[0] != values:
            self._options = values, SolverOptions(max_iterations=values[0], optimize_comfort=values[1],
                                                  restarts=values[2])  # fmt: skip
        return self._options[1]

    def text(self, labels: tuple) -> str:
        """``repr(labels)`` (the manikin's settings, the held weights, options and box), made again only when one
        of them is another (a keyed setting)."""
        last = self._text
        if last is None or not all(map(_same, last[0], labels)) or len(last[0]) != len(labels):
            last = self._text = labels, repr(labels)
        return last[1]

    def target(self, ob: bpy.types.Object, label: tuple, local: Matrix, feet: str) -> Target:
        """The Target of the empty ``ob`` (its settings ``label``, its matrix ``local`` in the armature's space,
        the manikin's Feet setting): the last frame's very Target when all of these are the same (the constraints
        built for it are then kept without comparing numbers)."""
        signs = tuple(math.copysign(1.0, v) for v in label[7:9])  # friction, weight: -0.0 == 0.0 but is another input
        key = (label, signs, feet, np.array(local).tobytes())
        last = self._targets.get(ob.name)
        if last is not None and last[0] == key:
            return last[1]
        rot, pos = _frame(local)
        s = ob.manikin_target
        target = Target(s.tcp, pos, rot, solved_lock(s.locked_axes(), s.support, feet), None, s.weight, s.support,
                        s.friction, None, s.enabled, s.priority_number())  # fmt: skip
        self._targets[ob.name] = key, target
        return target


def read_problem(
    arm: bpy.types.Object,
    live: bool = False,
    start: bool = True,
    reuse: SceneProblem | None = None,
    held: Held | None = None,
) -> SceneProblem:
    """The targets, loops and loads of ``arm`` as a solver Problem; raises ManikinError naming the empty.
    ``start``: also read the pose as the start point (a bake, which starts each frame from the previous one's
    solution, does without: ``x0`` is then None). ``reuse``: the problem read before (a bake's previous frame);
    when only the targets' poses changed, the new problem shares its constraints (what they built and keep).
    ``held``: what a bake read once (:class:`Held`, of this armature and scene); default: read now."""
    return _read_problem(arm, live, start, reuse, held)


def _read_problem(
    arm: bpy.types.Object, live: bool, start: bool, reuse: SceneProblem | None, held: Held | None
) -> SceneProblem:
    """:func:`read_problem` without reuse."""
    world = arm.matrix_world  # a copy on each read: read once
    arm_rot = np.array(world.to_3x3())
    if held is None or held.upright != arm_rot.tobytes():  # a bake checks again when the armature turned
        _check_upright(arm, arm_rot)
    held = Held(arm) if held is None else held
    held.upright = arm_rot.tobytes()
    model = held.model
    settings = arm.manikin
    to_local = world.inverted()
    x0 = read_x(arm) if start else None
    kin0 = None  # the pose's kinematics, for loop offsets only
    targets, loops, loads, labels, numbers, fixed = [], [], [], [], [], []
    for ob in members(arm, held.linked):
        s = ob.manikin_target
        label = (ob.name, s.role, s.tcp, s.other, tuple(s.lock), s.support, s.enabled, s.friction, s.weight,
                 s.priority)  # fmt: skip
        role, enabled = label[1], label[6]  # each property read costs: read once
        for name in label[2:4] if role == "LOOP" else label[2:3]:
            if name not in model.tcps:
                raise ManikinError(f"{ob.name}: unknown TCP {name!r} (known: {', '.join(sorted(model.tcps))})")
        if role == "TARGET":
            target = held.target(ob, label, to_local @ ob.matrix_world, settings.feet)
            targets.append(target)
            given = (target.position, target.rotation)
        elif role == "LOOP" and enabled:
            rot, pos = _frame(to_local @ ob.matrix_world)
            if kin0 is None:
                kin0 = model.forward((read_x(arm) if x0 is None else x0)[: model.n])
            other_rot, other_pos = kin0.tcp_frame(model.tcp(s.other))
            given = (other_rot.T @ (pos - other_pos), other_rot.T @ rot)  # the offset, unchanged by posing
            loops.append(Loop(s.tcp, s.other, *given, s.locked_axes(), None, s.weight))
        elif role == "LOAD" and enabled:
            given = (arm_rot.T @ np.array(s.force),)
            loads.append(ExternalLoad(s.tcp, *given))
        else:
            continue
        labels.append(label)
        numbers.extend(v.ravel() for v in given)
        if role != "TARGET":
            fixed.extend(v.ravel() for v in given)
    if not targets and not loops:
        raise ManikinError(f"{arm.name}: nothing to solve; add a target (Manikin > Add Target)")
    weights = held.weights(settings)  # one per registered standard comfort term
    try:
        groups = DEFAULT_GROUPS if settings.reduction else ()
        obstacles, shapes = scene_obstacles(arm, held.sources)
        numbers += shapes
        carried = held.carried
        options = held.options(settings, live)
        tail = (settings.feet, settings.balance, settings.floor, settings.self_collision, settings.comfort,
                settings.reduction, weights, options, held.box)  # fmt: skip
        text = "[" + ", ".join([*map(repr, labels), held.text(tail)]) + "]"  # repr([*labels, tail])
        # all but the targets' poses; obstacles by identity (unchanged shapes made from bounds are the same objects)
        setup = (id(model), text, np.concatenate(fixed + shapes).tobytes() if fixed or shapes else b"",
                 tuple(id(o) for o in obstacles))  # fmt: skip
        if reuse is not None and reuse.setup == setup and settings.feet != STEP:  # stepping: from the feet's targets
            problem = reuse.problem.with_targets(targets)
        else:
            problem = Problem(model, targets, loops, loads, settings.balance, weights, groups, floor=settings.floor,
                              obstacles=obstacles, self_collision=settings.self_collision, carried=carried)  # fmt: skip
            problem = stepping(problem) if settings.feet == STEP else problem
    except ManikinError as exc:
        raise ManikinError(f"{arm.name}: {exc}") from None
    inputs = Inputs(text, np.concatenate(numbers) if numbers else np.zeros(0))
    warm = x0 if x0 is None or len(x0) == problem.n_x else x0[: model.n]  # remembered forces fit the same supports
    return SceneProblem(problem, warm, options, inputs, setup)


def _carried(arm: bpy.types.Object, model: Model) -> Carried | None:
    """``arm``'s carried box (the body but the holding hands keeps out of it), or None: none, or a TCP the body
    lacks (a renamed body file; the box is then not placed either)."""
    ob = find_carried(arm)
    if ob is None:
        return None
    spec = carried_spec(ob)
    return spec if all(tcp in model.tcps for tcp in spec.tcps) else None


def summarize(result: Result, scores: bool = True) -> dict:
    """What the sidebar and the overlay show, armature space, JSON-ready; ``scores``: with the ergonomics scores
    (:func:`ergonomics`, ~1 ms; a live drag leaves them out: ``pending`` is then True). ``closest``: the clearance
    pairs within their margin (as in the result file, plus ``below``: under the clearance by more than the solver's
    tolerance, and ``body``: a pair of two body parts) and ``capsules`` the body's collision capsules (start, end,
    radius; m) in this pose."""
    state = result.state
    problem = result.problem
    model = problem.model
    tau = state.statics.axis_loads()
    percent = percent_of_strength(tau, model.strength)
    rank = np.where(np.isfinite(percent) & ~model.prismatic, percent, -1.0)
    top = np.argsort(-rank, kind="stable")[:TOP_LOADS]
    corners = problem.contacts.corner_points(state.kin) if problem.contacts.n_vars else np.zeros((0, 3))
    parts = set(capsules_of(model).names)  # a pair with another body part (self-collision) is marked ``body``
    steps = steps_of(problem, state)
    stepped = set(FEET) if bounds_of(problem) is not None else set()
    return dict(
        converged=bool(result.converged),
        iterations=int(result.iterations),
        time_ms=1e3 * float(result.time_s),
        unmet=list(result.unmet),
        broken=list(result.broken),
        shortfall={name: shortfall_text(parts) for name, parts in result.shortfall.items()},
        residuals={k: float(v) for k, v in result.residuals.items()},
        comfort=float(result.comfort),
        comfort_parts={k: float(v) for k, v in result.comfort_parts.items()},
        com=[float(v) for v in result.com],
        contacts=[
            dict(tcp=c["tcp"], point=[float(v) for v in c["point"]], force=[float(v) for v in c["force"]])
            for c in result.contacts
        ],
        support_polygon=support_polygon(corners).tolist() if len(corners) else [],
        loads=[dict(tcp=ld.tcp.name, force=[float(v) for v in ld.force]) for ld in problem.loads],
        joint_loads=[(model.joint_names[j], float(tau[j]), float(percent[j])) for j in top if rank[j] >= 0],
        joint_percent={model.joint_names[j]: float(percent[j]) for j in range(model.n) if rank[j] >= 0},
        **(ergonomics(result) if scores else dict(pending=True)),
        closest=[
            dict(c.to_dict(), below=bool(c.distance < c.clearance - TOLERANCE), body=c.other in parts)
            for c in result.closest
        ],  # fmt: skip
        capsules=capsules(problem.model, state),
        moved={k: v for k, v in moved_supports(result).items() if k not in stepped},  # {tcp: {"mm", "deg"}}: supports
        # that ended away from their targets (a stepping foot's step is reported as a step instead)
        steps=[s.as_dict() for s in steps],  # May step: each foot's step (length m, direction and turn deg)
        step_lines=[s.text() for s in steps],  # "foot_r stepped 0.41 m, 8 deg left of forward, turned 3 deg"
        notes=floor_notes(result) + pushed_notes(result),  # hints: a support off the floor, pushed by an obstacle
        kernels=kernels.status(),  # which kernels solved: Numba's compiled ones or the NumPy code (and why)
    )


def capsules(model: Model, state: State) -> list[dict]:
    """The body's collision capsules in the pose ``state``: start, end (m, armature space) and radius (m)."""
    body = capsules_of(model)
    start, end = body.world(state.kin)
    return [dict(link=name, start=a.tolist(), end=b.tolist(), radius=float(r))
            for name, a, b, r in zip(body.names, start, end, body.radius, strict=True)]  # fmt: skip


def scores(result: Result) -> list[str]:
    """This pose's ergonomics as the sidebar shows them: each registered score's words, as ``python -m solver ergo``
    prints them (:meth:`~solver.ergonomics.base.Score.brief`: "RULA 3", ..., "L4/L5 1520 N, worksheet yellow")."""
    return ergonomics(result)["scores"]


def ergonomics(result: Result) -> dict:
    """``scores``: :func:`scores`' words; ``verdicts``: each score's words with their level and severity
    (:func:`solver.ergonomics.registry.verdicts`: "OWAS 2141", "action category 2: ...", 1)."""
    rated = verdicts(solver.evaluate(result, ErgoOptions())["frames"][0])
    return dict(scores=[v["text"] for v in rated], verdicts=rated)


def write_result(arm: bpy.types.Object, result: Result, scores: bool = True) -> None:
    """Pose the armature with the result (its carried box between the hands) and keep its summary for the sidebar
    and the overlay (``scores``: with the ergonomics scores; a live drag adds them later, :func:`write_scores`)."""
    write_pose(arm, result.x)
    follow_solve(arm, result.x)
    summary = summarize(result, scores)
    color_bones_by_load(arm, summary["joint_percent"])
    arm[RESULT_KEY] = json.dumps(summary)
    if ERROR_KEY in arm:
        del arm[ERROR_KEY]


def write_scores(arm: bpy.types.Object, result: Result) -> None:
    """Add ``result``'s ergonomics scores to the summary written without them (a live drag's), if it is still the one
    shown (a later Solve Pose wrote its own)."""
    text = arm.get(RESULT_KEY)
    summary = json.loads(text) if isinstance(text, str) else None
    if summary is None or not summary.pop("pending", False):
        return
    summary.update(ergonomics(result))
    arm[RESULT_KEY] = json.dumps(summary)
