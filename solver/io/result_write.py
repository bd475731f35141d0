"""Result -> the result file (JSON, README "result JSON"): enough to recompute balance and loads from it alone."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from ..result import Result
from .files import write_json
from .frame import Frame, frame_of_result
from .values import finite_or_none, floats, quaternion


def result_to_dict(result: Result, frame: int = 1) -> dict:
    """One frame of the result file: the solve's status and residuals, then the pose (:func:`frame_to_dict`)."""
    state = result.state
    targets = {
        name: dict(position=floats(pos), rotation=quaternion(rot))
        for name, (rot, pos) in result.problem.target_frames(state).items()
    }
    status = dict(
        frame=frame,
        converged=result.converged,
        stop=None if result.stop is None else result.stop.value,
        iterations=result.iterations,
        time_s=result.time_s,
        unmet=list(result.unmet),
        broken=list(result.broken),
        shortfall=result.shortfall,
        notes=list(result.notes),
        targets=targets,
        residuals=result.residuals,
        comfort=result.comfort,
        comfort_terms=result.comfort_parts,
        com=floats(result.com),
    )
    return status | frame_to_dict(frame_of_result(result, frame))


def frame_to_dict(f: Frame) -> dict:
    """The pose part of a result frame: gravity, joints, tcps, links, contacts and loads."""
    joints = {}
    for i, name in enumerate(f.joint_names):
        joints[name] = dict(
            value=float(f.joint_value[i]),
            min=finite_or_none(f.joint_range[i, 0]),
            max=finite_or_none(f.joint_range[i, 1]),
            type="prismatic" if f.prismatic[i] else "revolute",
            link=f.link_names[f.joint_link[i]],
        )
        if f.joint_strength is not None:
            joints[name]["strength"] = [finite_or_none(s) for s in f.joint_strength[i]]
        joints[name].update(position=floats(f.joint_position[i]), axis=floats(f.joint_axis[i]))
    tcps = {
        name: dict(position=floats(p), rotation=quaternion(f.tcp_rotation[name]), link=f.link_names[f.tcp_link[name]])
        for name, p in f.tcp_position.items()
    }
    links = [
        dict(name=name, parent=None if f.link_parent[i] < 0 else f.link_names[f.link_parent[i]],
             mass=float(f.link_mass[i]), com=floats(f.link_com[i]))
        for i, name in enumerate(f.link_names)
    ]  # fmt: skip
    return dict(
        gravity=floats(f.gravity),
        joints=joints,
        tcps=tcps,
        links=links,
        contacts={tcp: dict(point=floats(p), force=floats(fc), moment=floats(m)) for tcp, p, fc, m in f.contacts},
        loads=[dict(tcp=tcp, point=floats(p), force=floats(fc)) for tcp, p, fc in f.loads],
    )


def result_document(frames: Iterable[tuple[int, Result]], scenario: str | Path | None = None) -> dict:
    """The whole result file: {"scenario": path of the scenario (if any), "frames": [...]}."""
    document: dict = {} if scenario is None else {"scenario": str(scenario)}
    document["frames"] = [result_to_dict(result, number) for number, result in frames]
    return document


def write_result(
    path: str | Path, results: Result | Iterable[tuple[int, Result]], scenario: str | Path | None = None
) -> Path:
    """Write a result file: one Result (frame 1) or (frame, Result) pairs as :func:`solver.solve_motion` yields;
    ``scenario`` names the scenario file (the ergonomics finds the manikin there). Atomic; returns the path."""
    pairs = [(1, results)] if isinstance(results, Result) else results
    return write_json(Path(path), result_document(pairs, scenario))
