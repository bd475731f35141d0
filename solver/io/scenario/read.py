"""Scenario TOML -> :class:`~solver.problem.scenario.Scenario`: every key checked, every problem one ScenarioError line.

The format: docs/reference/scenario-file.md. Units: m, rad, N, kg; rotations are quaternions (w, x, y, z).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...body.model import GRAVITY, Model
from ...body.reduction import DEFAULT_GROUPS, GROUPS
from ...collision.carried import Carried
from ...comfort import STANDARD_TERMS, ComfortWeights
from ...errors import ManikinError, ScenarioError
from ...options import AXES, DEFAULT_OPTIONS, MAX_FRAME, MAX_FRAMES, MAX_WEIGHT, MIN_WEIGHT, MotionLimits, SolverOptions
from ...problem.problem import Problem
from ...problem.scenario import Scenario
from ...problem.specs import MAX_DISTANCE, MAX_FORCE, PRIORITIES, ExternalLoad, Loop, ProblemSpec, Target
from ...problem.tracks import Key, Track, targets_at
from ...stance.step_problem import FEET_MODES, PLANTED, STEP, stepping
from ..files import read_text
from ..files import read_toml as read_toml_file
from ..table_reader import TableReader
from .bodies import load_body
from .obstacles import read_obstacles

SECTIONS = {"manikin", "solver", "comfort", "start", "targets", "loads", "loops", "frame", "motion", "name",
            "description", "floor", "self_collision", "obstacles", "carried", "stance"}  # fmt: skip
TARGET_KEYS = {"tcp", "position", "rotation", "lock", "operator", "weight", "support", "friction", "sole", "enabled",
               "priority", "name", "keys"}  # fmt: skip
FRAME = "a whole frame number"
MAX_LOAD_MASS = 1e5  # kg, a load's mass (MAX_FORCE / g, rounded)
MAX_SOLE = 10.0  # m, a sole corner's distance from its TCP
MAX_TURN = 4 * np.pi  # rad, a start value (two turns either way; values outside the joint's range are clipped)
LOOP_KEYS = {"tcp", "other", "offset_position", "offset_rotation", "lock", "operator", "weight"}


def read_toml(path: Path) -> TableReader:
    """A reader of the TOML file ``path``; an empty, missing or malformed file is one ScenarioError line."""
    data = read_toml_file(path, ScenarioError)
    if not data and not read_text(path, ScenarioError).strip():
        raise ScenarioError(f"{path}: the file is empty; expected a scenario with [manikin] and [[targets]]")
    return TableReader(path, data, error=ScenarioError)


def load_scenario(path: str | Path, feet: str | None = None) -> Scenario:
    """Read and validate a scenario file into a ready-to-solve :class:`Scenario`; ``feet`` ("planted" or "step")
    overrides its [stance] feet."""
    return _scenario(read_toml(Path(path)), feet=feet)


def scenario_from_dict(data: dict, path: str | Path, model: Model | None = None) -> Scenario:
    """A scenario from its parsed tables ``data`` (as a scenario file's TOML), as if read from ``path``: errors name
    it and relative paths in it (a body file, an obstacle mesh) are found beside it. ``model``: the body its
    [manikin] names, built already (a study's worker reuses it for many runs). A study's runs use it."""
    return _scenario(TableReader(Path(path), data, error=ScenarioError), model)


def _scenario(root: TableReader, model: Model | None = None, feet: str | None = None) -> Scenario:
    """Validate the scenario tables of ``root`` into a ready-to-solve :class:`Scenario`."""
    path = Path(root.path)
    root.known(SECTIONS)
    model = model or read_manikin(root.table("manikin"))
    balance, reduction, options = _read_solver(root.table("solver"))
    weights = _read_comfort(root.table("comfort"))
    read = [_read_target(t, model) for t in root.table_list("targets")]
    targets = [target for target, _ in read]
    tracks = [Track(i, keys) for i, (_, keys) in enumerate(read) if keys]
    loads = [_read_load(t, model) for t in root.table_list("loads")]
    loops = [_read_loop(t, model) for t in root.table_list("loops")]
    if not targets and not loops:
        raise root.fail("targets", "at least one [[targets]] entry")
    if balance and not any(t.support and t.enabled for t in targets):
        raise root.fail("targets", "a target with support = true when [solver] balance = true")
    frames, limits = _read_motion(root, tracks)
    obstacles = read_obstacles(root.table_list("obstacles"), path.parent)
    carried = _read_carried(root, model)
    floor, self_collision = _enabled(root, "floor"), _enabled(root, "self_collision")
    feet = feet or _read_feet(root)
    try:
        spec = ProblemSpec(targets_at(targets, tracks, frames[0]), loops, loads, balance, weights, reduction,
                           floor=floor, obstacles=obstacles, self_collision=self_collision, carried=carried)
        problem = Problem(model, spec)
        problem = stepping(problem) if feet == STEP else problem
    except ManikinError as exc:
        raise ScenarioError(f"{path}: {exc}") from None
    start = _read_start(root.table("start"), model, problem)
    return Scenario(path, model, problem, options, start, frames, tracks, limits, carried)


def load_motion(path: str | Path) -> Scenario:
    """A scenario that is a motion (keyed targets or a [motion] frame range); a single pose is a ScenarioError."""
    scenario = load_scenario(path)
    if not scenario.is_motion:
        raise ScenarioError(
            f"{scenario.path}: motion: expected keyed targets ([[targets.keys]]) or a [motion] range of frames, "
            "got a single pose"
        )
    return scenario


def scenario_manikin(path: Path) -> Model:
    """The body named by the [manikin] table of the scenario file ``path`` (the rest of the file unread)."""
    return read_manikin(read_toml(path).table("manikin"))


def read_manikin(t: TableReader) -> Model:
    """[manikin] preset = "name" or file = "body.toml" (relative to the scenario's folder)."""
    t.known({"preset", "file"})
    which = t.exactly_one("preset", "file", 'exactly one of preset = "male_50" or file = "body.toml"')
    try:
        if which == "preset":
            return load_body(preset=t.string("preset"))
        body = Path(t.string("file"))
        return load_body(file=body if body.is_absolute() else Path(t.path).parent / body)
    except ManikinError as exc:
        raise ScenarioError(f"{t.path}: manikin: {exc}") from None


def _read_comfort(t: TableReader) -> ComfortWeights:
    """[comfort]: a weight per standard comfort term (:data:`solver.comfort.STANDARD_TERMS`), by its name."""
    t.known(set(STANDARD_TERMS))
    return ComfortWeights(**{name: t.number(name, term.weight, 0.0, MAX_WEIGHT)
                             for name, term in STANDARD_TERMS.items()})  # fmt: skip


def _read_solver(t: TableReader) -> tuple[bool, tuple[str, ...], SolverOptions]:
    """[solver]: balance, the reduction groups and the iteration options."""
    t.known({"balance", "reduction", "max_iterations", "comfort", "restarts"})
    options = SolverOptions(
        max_iterations=t.integer("max_iterations", DEFAULT_OPTIONS.max_iterations, 1, 100000),
        optimize_comfort=t.boolean("comfort", True),
        restarts=t.integer("restarts", DEFAULT_OPTIONS.restarts, 0, 10),
    )
    return t.boolean("balance", True), _read_reduction(t), options


def _read_reduction(t: TableReader) -> tuple[str, ...]:
    """[solver] reduction = true (every group but the opt-in shoulder rhythm), false, or a list of groups."""
    value = t.get("reduction", False)
    if isinstance(value, bool):
        return DEFAULT_GROUPS if value else ()
    if isinstance(value, list) and all(isinstance(g, str) for g in value) and all(g in GROUPS for g in value):
        return tuple(value)
    raise t.fail("reduction", "true, false or a list of groups from " + ", ".join(GROUPS), value)


def _read_motion(root: TableReader, tracks: list[Track]) -> tuple[list[int], MotionLimits | None]:
    """Frames to solve and per-frame change limits: [motion] start/end/step, else the keys' span."""
    motion = root.table("motion")
    motion.known({"start", "end", "step", "max_joint_change", "max_root_shift", "bounded"})
    keyed = [k.frame for track in tracks for k in track.keys]
    first = root.integer("frame", 1, -MAX_FRAME, MAX_FRAME, FRAME) if not keyed else min(keyed)
    start = motion.integer("start", first, -MAX_FRAME, MAX_FRAME, FRAME)
    end = motion.integer("end", max(keyed) if keyed else start, start, MAX_FRAME, FRAME)
    step = motion.integer("step", 1, 1, MAX_FRAMES)
    frames = list(range(start, end + 1, step))
    if len(frames) > MAX_FRAMES:
        raise motion.fail("end", f"at most {MAX_FRAMES} frames (end - start) / step + 1", len(frames))
    limits = MotionLimits(
        motion.number("max_joint_change", MotionLimits.max_joint_change, 1e-6, 10.0, "rad"),
        motion.number("max_root_shift", MotionLimits.max_root_shift, 1e-6, 100.0, "m"),
    )
    return frames, limits if motion.boolean("bounded", True) else None


def _read_target(t: TableReader, model: Model) -> tuple[Target, tuple[Key, ...]]:
    """One [[targets]] entry and its keys (empty unless the target is keyed)."""
    t.known(TARGET_KEYS)
    _lock_or_operator(t)
    sole = None
    if "sole" in t.data:
        sole = t.points("sole", 2, "a list of [x, y] corners in the TCP frame, m")
        if np.abs(sole).max() > MAX_SOLE:
            raise t.fail("sole", f"corners within +-{MAX_SOLE:g} m of the TCP", t.get("sole"))
    keys = _read_keys(t)
    if keys and "position" not in t.data:
        position, rotation = keys[0].position, keys[0].rotation
    else:
        position, rotation = t.vector("position", 3, limit=MAX_DISTANCE, unit="m"), t.rotation("rotation")
    target = Target(
        tcp=t.choice("tcp", model.tcps, "a TCP of the manikin"),
        position=position,
        rotation=rotation,
        lock=t.lock("lock", AXES),
        operator=t.operator("operator"),
        weight=t.number("weight", 1.0, MIN_WEIGHT, MAX_WEIGHT),
        support=t.boolean("support", False),
        friction=t.number("friction", 0.6, 0.0, 10.0, "(friction coefficient)"),
        sole=sole,
        enabled=t.boolean("enabled", True),
        priority=_priority(t),
    )
    return target, keys


def _enabled(root: TableReader, name: str) -> bool:
    """[floor] enabled (every body part stays above z = 0) or [self_collision] enabled (hands and forearms out of
    the trunk, head and thighs, shanks apart); both default true."""
    if name not in root.data:
        return True
    t = root.table(name)
    t.known({"enabled"})
    return t.boolean("enabled", True)


def _read_carried(root: TableReader, model: Model) -> Carried | None:
    """[carried] size = [across, depth, height] (m), tcps = [first, second], name: a box held between two TCPs."""
    if "carried" not in root.data:
        return None
    t = root.table("carried")
    t.known({"size", "tcps", "name"})
    t.required("size", "tcps")
    size = t.vector("size", 3, limit=MAX_DISTANCE, unit="m")
    if (size <= 0).any():
        raise t.fail("size", "3 edge lengths > 0 (m)", t.get("size"))
    tcps = t.get("tcps")
    if not (isinstance(tcps, list) and len(tcps) == 2 and all(isinstance(n, str) and n in model.tcps for n in tcps)):
        raise t.fail("tcps", 'two TCPs of the manikin, e.g. ["hand_r", "hand_l"]', tcps)
    if tcps[0] == tcps[1]:
        raise t.fail("tcps", "two different TCPs", tcps)
    return Carried(size, (tcps[0], tcps[1]), t.string("name", "carried box"))


def _read_feet(root: TableReader) -> str:
    """[stance] feet = "planted" (the default: can the worker do this from here?) or "step" (:mod:`solver.stance`)."""
    t = root.table("stance")
    t.known({"feet"})
    return t.choice("feet", FEET_MODES, "one of") if "feet" in t.data else PLANTED


def _priority(t: TableReader) -> int | None:
    """``priority``: 1 (must hold) or 2 (as close as possible); absent: by the target's kind."""
    if "priority" not in t.data:
        return None
    value = t.get("priority")
    if isinstance(value, bool) or value not in PRIORITIES:
        raise t.fail("priority", "1 (must hold) or 2 (as close as possible)", value)
    return int(value)


def _read_keys(t: TableReader) -> tuple[Key, ...]:
    """[[targets.keys]] frame = N, position = [...], rotation = [...] (optional), sorted by frame."""
    keys = []
    for k in t.table_list("keys"):
        k.known({"frame", "position", "rotation"})
        frame = k.integer("frame", None, -MAX_FRAME, MAX_FRAME, FRAME)
        keys.append(Key(frame, k.vector("position", 3, limit=MAX_DISTANCE, unit="m"), k.rotation("rotation")))
    frames = [k.frame for k in keys]
    if len(set(frames)) != len(frames):
        raise t.fail("keys", "distinct frame numbers", frames)
    return tuple(sorted(keys, key=lambda k: k.frame))


def _read_load(t: TableReader, model: Model) -> ExternalLoad:
    """One [[loads]] entry: a force (N) or a mass (kg) held at a TCP."""
    t.known({"tcp", "force", "mass"})
    if t.exactly_one("force", "mass", "exactly one of force = [fx, fy, fz] (N) or mass = kg") == "force":
        force = t.vector("force", 3, limit=MAX_FORCE, unit="N")
    else:
        force = t.number("mass", low=0.0, high=MAX_LOAD_MASS, unit="kg") * GRAVITY
    return ExternalLoad(t.choice("tcp", model.tcps, "a TCP of the manikin"), force)


def _read_loop(t: TableReader, model: Model) -> Loop:
    """One [[loops]] entry: a TCP held on another TCP's frame."""
    t.known(LOOP_KEYS)
    _lock_or_operator(t)
    return Loop(
        tcp=t.choice("tcp", model.tcps, "a TCP of the manikin"),
        other=t.choice("other", model.tcps, "a TCP of the manikin"),
        offset_position=t.vector("offset_position", 3, [0.0, 0.0, 0.0], limit=MAX_DISTANCE, unit="m"),
        offset_rotation=t.rotation("offset_rotation"),
        lock=t.lock("lock", ("x", "y", "z")),
        operator=t.operator("operator"),
        weight=t.number("weight", 1.0, MIN_WEIGHT, MAX_WEIGHT),
    )


def _read_start(t: TableReader, model: Model, problem: Problem) -> np.ndarray:
    """[start.joints] name = value: the start pose (other joints zero), as solver variables x."""
    t.known({"joints"})
    theta = model.zero_pose()
    joints = t.table("joints")
    for name in joints.data:
        if name not in model.joint_names:
            raise joints.fail(name, "a joint name of the manikin (unknown joint)")
        i = model.joint_index(name)
        limit, unit = (MAX_DISTANCE, "m") if model.prismatic[i] else (MAX_TURN, "rad")
        theta[i] = joints.number(name, None, -limit, limit, unit)  # outside the joint's range: clipped into it
    return problem.to_x(problem.start(theta))


def _lock_or_operator(t: TableReader) -> None:
    """Refuse a target or loop that gives both: the operator would silently replace the lock."""
    if "lock" in t.data and "operator" in t.data:
        raise t.fail("lock", "either lock or operator, not both (an operator replaces the lock)")
