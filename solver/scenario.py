"""Scenario files (TOML) in, result files (JSON) out: the public interface shared by CLI, Blender and batch.

Every problem in a file raises :class:`ScenarioError` with one line naming the file, the key and what was
expected. Units: m, rad, N, kg; rotations are quaternions (w, x, y, z).
"""

from __future__ import annotations

import json
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .bodies import load_body
from .comfort import ComfortWeights
from .constraints import AXES
from .errors import ManikinError, ScenarioError, read_text
from .model import GRAVITY, Model
from .motion import Key, MotionLimits, Track, targets_at
from .options import DEFAULT_OPTIONS, SolverOptions
from .problem import MAX_DISTANCE, MAX_FORCE, ExternalLoad, Loop, Problem, Target
from .reduction import DEFAULT_GROUPS, GROUPS
from .result import Result
from .spatial import matrix_to_quat, quat_to_matrix

SECTIONS = {
    "manikin",
    "solver",
    "comfort",
    "start",
    "targets",
    "loads",
    "loops",
    "frame",
    "motion",
    "name",
    "description",
}


@dataclass
class Scenario:
    """A parsed scenario: the model, the problem (at the first frame), solver options, start pose, frames.

    ``tracks`` hold the keyed targets of a motion; :meth:`problem_at` gives the problem at any frame.
    """

    path: Path
    model: Model
    problem: Problem
    options: SolverOptions
    start: np.ndarray
    frames: list[int]
    tracks: list[Track]
    limits: MotionLimits | None

    @property
    def frame(self) -> int:
        return self.frames[0]

    def problem_at(self, frame: int) -> Problem:
        """The problem with every keyed target at its pose for ``frame``."""
        if not self.tracks:
            return self.problem
        return self.problem.with_targets(targets_at(self.problem.all_targets, self.tracks, frame))


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


class _Reader:
    """Typed access to a TOML table with error messages that name the file and the key."""

    def __init__(self, path: Path, data: dict, prefix: str = "") -> None:
        self.path, self.data, self.prefix = path, data, prefix

    def fail(self, key: str, expected: str, value: Any = None) -> ScenarioError:
        got = "" if value is None else f", got {value!r}"
        return ScenarioError(f"{self.path}: {self.prefix}{key}: expected {expected}{got}")

    def sub(self, key: str, data: dict) -> _Reader:
        return _Reader(self.path, data, f"{self.prefix}{key}.")

    def known(self, keys: set[str]) -> None:
        for key in self.data:
            if key not in keys:
                raise self.fail(key, "one of " + ", ".join(sorted(keys)) + " (unknown key)")

    def get(self, key: str, default: Any = None) -> Any:
        return self.data.get(key, default)

    def number(self, key: str, default: float | None = None, low: float = -math.inf, high: float = math.inf) -> float:
        value = self.data.get(key, default)
        if value is None:
            raise self.fail(key, "a number (missing)")
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise self.fail(key, "a finite number", value)
        if not low <= value <= high:
            raise self.fail(key, f"a number in [{low}, {high}]", value)
        return float(value)

    def boolean(self, key: str, default: bool) -> bool:
        value = self.data.get(key, default)
        if not isinstance(value, bool):
            raise self.fail(key, "true or false", value)
        return value

    def string(self, key: str, default: str | None = None) -> str:
        value = self.data.get(key, default)
        if not isinstance(value, str) or not value:
            raise self.fail(key, "a non-empty string", value)
        return value

    def vector(self, key: str, size: int, default: Any = None, limit: float = math.inf) -> np.ndarray:
        value = self.data.get(key, default)
        ok = isinstance(value, list) and len(value) == size and all(_is_number(v) for v in value)
        if not ok:
            raise self.fail(key, f"{size} finite numbers", value)
        if any(abs(v) > limit for v in value):
            raise self.fail(key, f"{size} numbers within +-{limit:g}", value)
        return np.asarray(value, dtype=float)

    def rotation(self, key: str) -> np.ndarray | None:
        if key not in self.data:
            return None
        q = self.vector(key, 4)
        if np.linalg.norm(q) < 1e-9:
            raise self.fail(key, "a non-zero quaternion [w, x, y, z]", self.data[key])
        return quat_to_matrix(q)

    def lock(self, key: str, default: tuple[str, ...]) -> tuple[str, ...]:
        value = self.data.get(key, list(default))
        if not isinstance(value, list) or not all(isinstance(a, str) and a in AXES for a in value):
            raise self.fail(key, f"a list of axes from {list(AXES)}", value)
        return tuple(value)

    def operator(self, key: str) -> np.ndarray | None:
        if key not in self.data:
            return None
        value = self.data[key]
        try:
            op = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise self.fail(key, "a list of rows of 6 numbers", value) from None
        if op.ndim != 2 or op.shape[1] != 6 or op.shape[0] == 0 or not np.isfinite(op).all():
            raise self.fail(key, "a list of rows of 6 finite numbers", value)
        return op

    def tcp(self, key: str, model: Model) -> str:
        name = self.string(key)
        if name not in model.tcps:
            raise self.fail(key, "a TCP of the manikin: " + ", ".join(sorted(model.tcps)), name)
        return name

    def table_list(self, key: str) -> list[_Reader]:
        value = self.data.get(key, [])
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
            raise self.fail(key, "an array of tables ([[...]])", value)
        return [_Reader(self.path, v, f"{self.prefix}{key}[{i}].") for i, v in enumerate(value)]

    def table(self, key: str) -> _Reader:
        value = self.data.get(key, {})
        if not isinstance(value, dict):
            raise self.fail(key, "a table", value)
        return self.sub(key, value)


def read_toml(path: Path) -> dict:
    """Parse a TOML file, turning every failure into a one-line ScenarioError."""
    text = read_text(path, ScenarioError)
    if not text.strip():
        raise ScenarioError(f"{path}: the file is empty; expected a scenario with [manikin] and [[targets]]")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{path}: malformed TOML ({exc})") from None


def load_scenario(path: str | Path) -> Scenario:
    """Read and validate a scenario file into a ready-to-solve :class:`Scenario`."""
    path = Path(path)
    root = _Reader(path, read_toml(path))
    root.known(SECTIONS)
    model = _read_manikin(root.table("manikin"), path)
    solver_t = root.table("solver")
    solver_t.known({"balance", "reduction", "max_iterations", "comfort", "restarts"})
    reduction = _read_reduction(solver_t)
    balance = solver_t.boolean("balance", True)
    options = SolverOptions(
        max_iterations=int(solver_t.number("max_iterations", DEFAULT_OPTIONS.max_iterations, 1, 100000)),
        optimize_comfort=solver_t.boolean("comfort", True),
        restarts=int(solver_t.number("restarts", DEFAULT_OPTIONS.restarts, 0, 10)),
    )
    comfort_t = root.table("comfort")
    comfort_t.known({"range", "load", "contact"})
    weights = ComfortWeights(
        comfort_t.number("range", 1.0, 0.0), comfort_t.number("load", 1.0, 0.0), comfort_t.number("contact", 0.01, 0.0)
    )
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
    try:
        problem = Problem(model, targets_at(targets, tracks, frames[0]), loops, loads, balance, weights, reduction)
    except ManikinError as exc:
        raise ScenarioError(f"{path}: {exc}") from None
    start = _read_start(root.table("start"), model, problem)
    return Scenario(path, model, problem, options, start, frames, tracks, limits)


def _read_reduction(t: _Reader) -> tuple[str, ...]:
    """[solver] reduction = true (every group but the opt-in shoulder rhythm), false, or a list of groups."""
    value = t.get("reduction", False)
    if isinstance(value, bool):
        return DEFAULT_GROUPS if value else ()
    if isinstance(value, list) and all(isinstance(g, str) for g in value) and all(g in GROUPS for g in value):
        return tuple(value)
    raise t.fail("reduction", "true, false or a list of groups from " + ", ".join(GROUPS), value)


def _read_motion(root: _Reader, tracks: list[Track]) -> tuple[list[int], MotionLimits | None]:
    """Frames to solve and per-frame change limits: [motion] start/end/step, else the keys' span."""
    motion = root.table("motion")
    motion.known({"start", "end", "step", "max_joint_change", "max_root_shift", "bounded"})
    keyed = [k.frame for track in tracks for k in track.keys]
    first = int(root.number("frame", 1, -1e9, 1e9)) if not keyed else min(keyed)
    start = int(motion.number("start", first, -1e9, 1e9))
    end = int(motion.number("end", max(keyed) if keyed else start, start, 1e9))
    step = int(motion.number("step", 1, 1, 1e6))
    frames = list(range(start, end + 1, step))
    if len(frames) > 100000:
        raise motion.fail("end", "at most 100000 frames")
    limits = MotionLimits(
        motion.number("max_joint_change", MotionLimits.max_joint_change, 1e-6, 10.0),
        motion.number("max_root_shift", MotionLimits.max_root_shift, 1e-6, 100.0),
    )
    return frames, limits if motion.boolean("bounded", True) else None


def _read_manikin(t: _Reader, path: Path) -> Model:
    t.known({"preset", "file"})
    if ("preset" in t.data) == ("file" in t.data):
        raise t.fail("preset", 'exactly one of preset = "male_50" or file = "body.toml"')
    try:
        if "preset" in t.data:
            return load_body(preset=t.string("preset"))
        body = Path(t.string("file"))
        return load_body(file=body if body.is_absolute() else path.parent / body)
    except ManikinError as exc:
        raise ScenarioError(f"{path}: manikin: {exc}") from None


def _read_target(t: _Reader, model: Model) -> tuple[Target, tuple[Key, ...]]:
    t.known(
        {
            "tcp",
            "position",
            "rotation",
            "lock",
            "operator",
            "weight",
            "support",
            "friction",
            "sole",
            "enabled",
            "name",
            "keys",
        }
    )
    sole = None
    if "sole" in t.data:
        value = t.data["sole"]
        ok = isinstance(value, list) and len(value) >= 1
        ok = ok and all(isinstance(p, list) and len(p) == 2 and all(_is_number(c) for c in p) for p in value)
        if not ok:
            raise t.fail("sole", "a list of [x, y] corners in the TCP frame, m (finite numbers)", value)
        sole = np.asarray(value, dtype=float)
    keys = _read_keys(t)
    if keys and "position" not in t.data:
        position, rotation = keys[0].position, keys[0].rotation
    else:
        position, rotation = t.vector("position", 3, limit=MAX_DISTANCE), t.rotation("rotation")
    target = Target(
        tcp=t.tcp("tcp", model),
        position=position,
        rotation=rotation,
        lock=t.lock("lock", AXES),
        operator=t.operator("operator"),
        weight=t.number("weight", 1.0, 1e-6),
        support=t.boolean("support", False),
        friction=t.number("friction", 0.6, 0.0, 10.0),
        sole=sole,
        enabled=t.boolean("enabled", True),
    )
    return target, keys


def _read_keys(t: _Reader) -> tuple[Key, ...]:
    """[[targets.keys]] frame = N, position = [...], rotation = [...] (optional), sorted by frame."""
    keys = []
    for k in t.table_list("keys"):
        k.known({"frame", "position", "rotation"})
        frame = k.number("frame", low=-1e9, high=1e9)
        if frame != int(frame):
            raise k.fail("frame", "a whole frame number", frame)
        keys.append(Key(int(frame), k.vector("position", 3, limit=MAX_DISTANCE), k.rotation("rotation")))
    frames = [k.frame for k in keys]
    if len(set(frames)) != len(frames):
        raise t.fail("keys", "distinct frame numbers", frames)
    return tuple(sorted(keys, key=lambda k: k.frame))


def _read_load(t: _Reader, model: Model) -> ExternalLoad:
    t.known({"tcp", "force", "mass"})
    if ("force" in t.data) == ("mass" in t.data):
        raise t.fail("force", "exactly one of force = [fx, fy, fz] (N) or mass = kg")
    if "force" in t.data:
        force = t.vector("force", 3, limit=MAX_FORCE)
    else:
        force = t.number("mass", low=0.0, high=MAX_FORCE / 9.81) * GRAVITY
    return ExternalLoad(t.tcp("tcp", model), force)


def _read_loop(t: _Reader, model: Model) -> Loop:
    t.known({"tcp", "other", "offset_position", "offset_rotation", "lock", "operator", "weight"})
    return Loop(
        tcp=t.tcp("tcp", model),
        other=t.tcp("other", model),
        offset_position=t.vector("offset_position", 3, [0.0, 0.0, 0.0], limit=MAX_DISTANCE),
        offset_rotation=t.rotation("offset_rotation"),
        lock=t.lock("lock", ("x", "y", "z")),
        operator=t.operator("operator"),
        weight=t.number("weight", 1.0, 1e-6),
    )


def _read_start(t: _Reader, model: Model, problem: Problem) -> np.ndarray:
    t.known({"joints"})
    theta = model.zero_pose()
    joints = t.table("joints")
    for name in joints.data:
        if name not in model.joint_names:
            raise joints.fail(name, "a joint name of the manikin (unknown joint)")
        theta[model.joint_index(name)] = joints.number(name)
    return problem.to_x(problem.start(theta))


def _vec(v: np.ndarray) -> list[float]:
    return [float(a) for a in v]


def _limit(v: float) -> float | None:
    return float(v) if math.isfinite(v) else None


def result_to_dict(result: Result, frame: int = 1) -> dict:
    """One frame of the result file: enough to recompute balance and joint loads from the file alone."""
    problem = result.problem
    model = problem.model
    state = result.state
    kin = state.kin
    joints = {}
    for i, name in enumerate(model.joint_names):
        joints[name] = dict(
            value=float(result.theta[i]),
            min=_limit(model.lower[i]),
            max=_limit(model.upper[i]),
            type="prismatic" if model.prismatic[i] else "revolute",
            link=model.link_names[i],
            strength=[_limit(model.strength[i, 0]), _limit(model.strength[i, 1])],
            position=_vec(kin.position[i]),
            axis=_vec(kin.axis[i]),
        )
    tcps = {}
    for name, tcp in model.tcps.items():
        rot, pos = kin.tcp_frame(tcp)
        tcps[name] = dict(position=_vec(pos), rotation=_vec(matrix_to_quat(rot)), link=model.link_names[tcp.link])
    links = [
        dict(
            name=model.link_names[i],
            parent=None if model.parent[i] < 0 else model.link_names[model.parent[i]],
            mass=float(model.mass[i]),
            com=_vec(kin.com[i]),
        )
        for i in range(model.n)
    ]
    targets = {}
    for name, (rot, pos) in problem.target_frames(state).items():
        targets[name] = dict(position=_vec(pos), rotation=_vec(matrix_to_quat(rot)))
    contacts = {
        c["tcp"]: dict(point=_vec(c["point"]), force=_vec(c["force"]), moment=_vec(c["moment"]))
        for c in result.contacts
    }
    loads = [
        dict(tcp=ld.tcp.name, point=_vec(p), force=_vec(ld.force))
        for ld, p in zip(problem.loads, state.statics.load_points, strict=True)
    ]
    return dict(
        frame=frame,
        converged=result.converged,
        iterations=result.iterations,
        time_s=result.time_s,
        unmet=list(result.unmet),
        notes=list(result.notes),
        targets=targets,
        residuals=result.residuals,
        comfort=result.comfort,
        comfort_terms=result.comfort_parts,
        com=_vec(result.com),
        gravity=_vec(GRAVITY),
        joints=joints,
        tcps=tcps,
        links=links,
        contacts=contacts,
        loads=loads,
    )


def scenario_to_dict(
    problem: Problem,
    manikin: dict,
    options: SolverOptions = DEFAULT_OPTIONS,
    start: np.ndarray | None = None,
    name: str | None = None,
) -> dict:
    """A scenario as the TOML tables :func:`load_scenario` reads: ``manikin`` is {"preset": ...} or {"file": ...}.

    ``start`` (joint values, or joints + forces) becomes [start.joints] for its non-zero joints.
    """
    model = problem.model
    data: dict[str, Any] = {"name": name} if name else {}
    data["manikin"] = dict(manikin)
    data["solver"] = dict(
        balance=problem.balance,
        max_iterations=options.max_iterations,
        comfort=options.optimize_comfort,
        restarts=options.restarts,
    )
    if problem.reduction_groups:
        data["solver"]["reduction"] = list(problem.reduction_groups)
    w = problem.comfort.weights
    data["comfort"] = dict(range=w.range, load=w.load, contact=w.contact)
    if start is not None:
        joints = {n: float(v) for n, v in zip(model.joint_names, start[: model.n], strict=True) if abs(v) > 1e-12}
        if joints:
            data["start"] = {"joints": joints}
    data["targets"] = [_target_table(t) for t in problem.all_targets]
    data["loads"] = [dict(tcp=ld.tcp, force=_vec(ld.force)) for ld in problem.load_specs]
    data["loops"] = [_loop_table(lp) for lp in problem.loops]
    return {k: v for k, v in data.items() if v != []}


def _relaxation(table: dict, lock: tuple[str, ...], operator: np.ndarray | None) -> None:
    if operator is None:
        table["lock"] = list(lock)
    else:
        table["operator"] = [_vec(row) for row in np.asarray(operator, dtype=float)]


def _target_table(t: Target) -> dict:
    table: dict[str, Any] = dict(tcp=t.tcp, position=_vec(t.position))
    if t.rotation is not None:
        table["rotation"] = _vec(matrix_to_quat(np.asarray(t.rotation, dtype=float)))
    _relaxation(table, t.lock, t.operator)
    table.update(weight=float(t.weight), support=bool(t.support), friction=float(t.friction), enabled=bool(t.enabled))
    if t.sole is not None:
        table["sole"] = [_vec(p) for p in np.asarray(t.sole, dtype=float)]
    return table


def _loop_table(lp: Loop) -> dict:
    table: dict[str, Any] = dict(tcp=lp.tcp, other=lp.other, offset_position=_vec(lp.offset_position))
    if lp.offset_rotation is not None:
        table["offset_rotation"] = _vec(matrix_to_quat(np.asarray(lp.offset_rotation, dtype=float)))
    _relaxation(table, lp.lock, lp.operator)
    table["weight"] = float(lp.weight)
    return table


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | float):
        if not math.isfinite(value):
            raise ScenarioError(f"cannot write the non-finite number {value!r} to a scenario")
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)  # a JSON string is a valid TOML basic string
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    raise ScenarioError(f"cannot write {type(value).__name__} values to a scenario")


def _toml_table(lines: list[str], header: str, table: dict) -> None:
    """``header`` ("[a.b]" or "[[a]]") with its plain keys, then its sub-tables as [a.b.c] and its arrays of
    tables as [[a.c]] (e.g. a target's ``[[targets.keys]]``, which attach to the ``[[targets]]`` just written)."""
    plain = {k: v for k, v in table.items() if not isinstance(v, dict) and not _is_table_array(v)}
    if plain or header.startswith("[[") or not any(isinstance(v, dict) for v in table.values()):
        lines.append(header)
        lines.extend(f"{_toml_key(k)} = {_toml_value(v)}" for k, v in plain.items())
        lines.append("")
    _toml_children(lines, header.strip("[]") + ".", table)


def _toml_children(lines: list[str], prefix: str, table: dict) -> None:
    """The sub-tables ([prefix.k]) and arrays of tables ([[prefix.k]]) of ``table``."""
    for k, v in table.items():
        if isinstance(v, dict):
            _toml_table(lines, f"[{prefix}{_toml_key(k)}]", v)
        elif _is_table_array(v):
            for item in v:
                _toml_table(lines, f"[[{prefix}{_toml_key(k)}]]", item)


def _toml_key(key: str) -> str:
    return key if key.replace("_", "").replace("-", "").isalnum() and key.isascii() else json.dumps(key)


def _is_table_array(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def dumps_scenario(data: dict) -> str:
    """TOML text of a scenario dict (from :func:`scenario_to_dict`); ``load_scenario`` reads it back."""
    lines = [
        f"{_toml_key(k)} = {_toml_value(v)}"
        for k, v in data.items()
        if not isinstance(v, dict) and not _is_table_array(v)
    ]
    if lines:
        lines.append("")
    _toml_children(lines, "", data)
    return "\n".join(lines).rstrip() + "\n"
