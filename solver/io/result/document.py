"""Result -> the plain values of a result file (the result JSON): enough to recompute balance and loads from it alone.

Two formats, both written frame by frame (:mod:`.write`): the result JSON (``{"scenario", "frames"}``,
each frame its status and its whole pose) and the compact JSON Lines file for long motions (a header line with
the manikin's model once, then per frame the status, the joint values, contacts and loads). A frame's status is
built in one place, :func:`frame_status`, for both.
"""

from __future__ import annotations

from collections.abc import Iterable
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ...collision.carried import CLEARANCE
from ...iteration.result import Result
from ...stance.report import step_dicts
from ..values import finite_or_none, floats, quaternion
from .frame import Frame, frame_of_result
from .model_json import model_to_dict

if TYPE_CHECKING:
    from ...body.model import Model
    from ...body.state import State
    from ...constraints.carried_clearance import CarriedClearance

COMPACT_FORMAT = "manikin-result-lines"  # the "format" of a compact file's header line
COMPACT_VERSION = 1


def frame_status(result: Result, frame: int, state: State) -> dict:
    """How the solve of one frame went (every field of a result frame that is not the pose): frame, converged,
    stop, iterations, time_s, unmet, notes, targets (world frames), residuals, comfort, comfort_terms, com, and the
    closest pairs within the clearance rows' margin (:meth:`~solver.constraints.clearance.Closeness.to_dict`: pair,
    part, other, distance, clearance, point, other_point; nearest first); with a carried box, ``carried``
    (:func:`carried_entry`); ``feet`` ("planted" or "step") and, stepping, ``steps`` (:mod:`solver.stance.report`)."""
    problem = result.problem
    targets = {
        name: {"position": floats(pos), "rotation": rotation_quaternion(rot)}
        for name, (rot, pos) in problem.target_frames(state).items()
    }
    status = {
        "frame": frame,
        "converged": result.converged,
        "stop": None if result.stop is None else result.stop.value,
        "iterations": result.iterations,
        "time_s": result.time_s,
        "unmet": list(result.unmet),
        "broken": list(result.broken),
        "shortfall": result.shortfall,
        "notes": list(result.notes),
        "targets": targets,
        "residuals": result.residuals,
        "comfort": result.comfort,
        "comfort_terms": result.comfort_parts,
        "com": floats(result.com),
        "closest": [pair.to_dict() for pair in result.closest],
    }
    if problem.carried_constraint is not None:
        status["carried"] = carried_entry(problem.carried_constraint, state)
    steps = step_dicts(result)  # stepping feet: each step's foot, length (m), direction and turn (deg), start, end
    status["feet"] = "planted" if steps is None else "step"
    if steps is not None:
        status["steps"] = steps
    return status


@lru_cache(maxsize=256)  # a body's TCPs, targets and carried box: the unchanged ones stay in
def _quaternion_of_bits(bits: bytes) -> tuple[float, ...]:
    """:func:`~solver.io.values.quaternion` of the rotation matrix whose 9 float64 are ``bits``."""
    return tuple(quaternion(np.frombuffer(bits).reshape(3, 3)))


def rotation_quaternion(rotation: np.ndarray) -> list[float]:
    """:func:`~solver.io.values.quaternion` of a rotation matrix, remembered by its bits: a target holds its
    rotation frame after frame (the same bits, the same quaternion)."""
    return list(_quaternion_of_bits(np.asarray(rotation, dtype=float).tobytes()))


def carried_entry(constraint: CarriedClearance, state: State) -> dict:
    """The carried box where the solver kept the body out of it: name, size (m), tcps (the two holding TCPs), center
    (m, world) and rotation (quaternion [w, x, y, z]; columns x first TCP -> second, z as near up as that allows),
    clearance (m) and excluded (the capsules its rows leave out: those on the holding TCPs' links)."""
    centre, rotation = constraint.frame(state)
    carried = constraint.carried
    return dict(name=carried.name, size=floats(carried.size), tcps=list(carried.tcps), center=floats(centre),
                rotation=rotation_quaternion(rotation), clearance=CLEARANCE,
                excluded=list(constraint.excluded))  # fmt: skip


def result_to_dict(result: Result, frame: int = 1, state: State | None = None) -> dict:
    """One frame of the result JSON: the status (:func:`frame_status`), then the pose (:func:`frame_to_dict`);
    ``state``: the result's state if the caller has it (saves recomputing it)."""
    state = result.state if state is None else state
    return frame_status(result, frame, state) | frame_to_dict(frame_of_result(result, frame, state))


def compact_frame_dict(result: Result, frame: int = 1, state: State | None = None) -> dict:
    """One frame of the compact file: the status, ``joint_values`` (rad or m, in the header model's joint order),
    ``contacts`` and ``loads`` as in the result JSON."""
    state = result.state if state is None else state
    status = frame_status(result, frame, state)
    status["joint_values"] = floats(result.theta)
    status.update(compact_wrenches(result, state))
    return status


def compact_wrenches(result: Result, state: State) -> dict:
    """The last keys of a compact frame: ``contacts`` {tcp: {point, force, moment}} and ``loads`` [{tcp, point,
    force}] (m, N, N*m)."""
    loads = zip(result.problem.loads, state.statics.load_points, strict=True)
    return {
        "contacts": {c["tcp"]: {"point": floats(c["point"]), "force": floats(c["force"]),
                                "moment": floats(c["moment"])} for c in result.contacts},
        "loads": [{"tcp": ld.tcp.name, "point": floats(p), "force": floats(ld.force)} for ld, p in loads],
    }  # fmt: skip


def compact_header(model: Model, scenario: str | Path | None) -> dict:
    """The first line of a compact file: its format and version, the scenario (if any) and the model."""
    from ...body.model import GRAVITY

    return dict(format=COMPACT_FORMAT, version=COMPACT_VERSION, scenario=None if scenario is None else str(scenario),
                gravity=floats(GRAVITY), model=model_to_dict(model))  # fmt: skip


def frame_to_dict(f: Frame, slot: str | None = None) -> dict:
    """The pose part of a result frame: gravity, joints, tcps, links, contacts, loads and the body's collision
    shapes (capsules: link, world end points m, radius m). ``slot``: put in place of every value that changes from
    frame to frame (a number, a list of numbers, the contacts, the loads), for :mod:`.frame_text`'s template."""
    moving = _moving(f) if slot is None else _slots(f, slot)
    ranges = [[finite_or_none(lo), finite_or_none(hi)] for lo, hi in f.joint_range.tolist()]
    strength = None if f.joint_strength is None else f.joint_strength.tolist()
    kinds = ["prismatic" if p else "revolute" for p in f.prismatic.tolist()]
    value, position, axis = moving["value"], moving["position"], moving["axis"]
    joints = {}
    for i, name in enumerate(f.joint_names):
        joints[name] = dict(value=value[i], min=ranges[i][0], max=ranges[i][1], type=kinds[i],
                            link=f.link_names[f.joint_link[i]])  # fmt: skip
        if strength is not None:
            joints[name]["strength"] = [finite_or_none(s) for s in strength[i]]
        joints[name].update(position=position[i], axis=axis[i])
    tcps = {
        name: dict(position=p, rotation=q, link=f.link_names[f.tcp_link[name]])
        for name, p, q in zip(f.tcp_position, moving["tcp_position"], moving["tcp_rotation"], strict=True)
    }
    parents, masses, coms = f.link_parent.tolist(), f.link_mass.tolist(), moving["com"]
    links = [
        dict(name=name, parent=None if parents[i] < 0 else f.link_names[parents[i]], mass=masses[i], com=coms[i])
        for i, name in enumerate(f.link_names)
    ]
    shapes = zip(f.collision_shapes, moving["start"], moving["end"], strict=True)
    return dict(
        gravity=moving["gravity"],
        joints=joints,
        tcps=tcps,
        links=links,
        contacts=moving["contacts"],
        loads=moving["loads"],
        collision_shapes=[dict(link=s[0], start=a, end=b, radius=s[3]) for s, a, b in shapes],
    )


def _moving(f: Frame) -> dict:
    """The values of a pose that change from frame to frame, as JSON takes them (see :func:`frame_to_dict`)."""
    return dict(
        gravity=floats(f.gravity),
        value=f.joint_value.tolist(),
        position=f.joint_position.tolist(),
        axis=f.joint_axis.tolist(),
        tcp_position=[floats(p) for p in f.tcp_position.values()],
        tcp_rotation=[quaternion(f.tcp_rotation[name]) for name in f.tcp_position],
        com=f.link_com.tolist(),
        contacts=contacts_dict(f),
        loads=loads_list(f),
        start=[a.tolist() for _, a, _, _ in f.collision_shapes],
        end=[b.tolist() for _, _, b, _ in f.collision_shapes],
    )


def _slots(f: Frame, slot: str) -> dict:
    """:func:`_moving` with ``slot`` for each value (lists of numbers: a list holding ``slot``)."""
    n, k, m = len(f.joint_names), len(f.tcp_position), len(f.collision_shapes)
    row = [slot]
    return dict(gravity=slot, value=[slot] * n, position=[row] * n, axis=[row] * n, tcp_position=[row] * k,
                tcp_rotation=[row] * k, com=[row] * len(f.link_names), contacts=slot, loads=slot, start=[row] * m,
                end=[row] * m)  # fmt: skip


def contacts_dict(f: Frame) -> dict:
    """A frame's contact wrenches as the result JSON has them: {tcp: {point, force, moment}}."""
    return {tcp: dict(point=floats(p), force=floats(fc), moment=floats(m)) for tcp, p, fc, m in f.contacts}


def loads_list(f: Frame) -> list[dict]:
    """A frame's external loads as the result JSON has them: [{tcp, point, force}]."""
    return [dict(tcp=tcp, point=floats(p), force=floats(fc)) for tcp, p, fc in f.loads]


def result_document(frames: Iterable[tuple[int, Result]], scenario: str | Path | None = None) -> dict:
    """The whole result JSON in memory: {"scenario": path of the scenario (if any), "frames": [...]} (for a few
    frames; files are written frame by frame by :func:`write_result`)."""
    document: dict = {} if scenario is None else {"scenario": str(scenario)}
    document["frames"] = [result_to_dict(result, number) for number, result in frames]
    return document
