"""A problem (with its manikin, options and start pose) -> the scenario tables :func:`load_scenario` reads -> TOML.

``scenario_to_dict`` gives plain data (the Blender layer adds keys to it), ``dumps_scenario`` its TOML text and
``write_scenario`` the file. Rotations are written as quaternions (w, x, y, z). Mesh obstacles: the data and its
text hold them inline (vertices and faces: text has no folder to put files in); ``write_scenario`` moves each into
an OBJ file beside the TOML (:mod:`.obstacle_files`) unless asked for ``inline`` or writing to standard output.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ...collision.carried import Carried
from ...errors import ScenarioError
from ...options import DEFAULT_OPTIONS, SolverOptions
from ...problem.problem import Loop, Problem, Target
from ..files import STDOUT, write_text, write_texts
from ..toml_write import dumps_toml
from ..values import floats, quaternion
from .obstacle_files import mesh_files
from .obstacles import obstacle_table


def scenario_to_dict(
    problem: Problem,
    manikin: dict,
    options: SolverOptions = DEFAULT_OPTIONS,
    start: np.ndarray | None = None,
    name: str | None = None,
    carried: Carried | None = None,
) -> dict:
    """A scenario as the TOML tables :func:`load_scenario` reads, from the problem's spec: ``manikin`` is
    {"preset": ...} or {"file": ...}.

    ``start`` (joint values, or joints + forces) becomes [start.joints] for its non-zero joints; ``carried`` (by
    default the problem's own) becomes [carried].
    """
    spec = problem.spec
    carried = spec.carried if carried is None else carried
    model = problem.model
    data: dict[str, Any] = {"name": name} if name else {}
    data["manikin"] = dict(manikin)
    data["solver"] = dict(
        balance=spec.balance,
        max_iterations=options.max_iterations,
        comfort=options.optimize_comfort,
        restarts=options.restarts,
    )
    if spec.reduction:
        data["solver"]["reduction"] = list(spec.reduction)
    if spec.weights is None:
        raise ScenarioError("a problem with comfort terms of its own (not the standard ones) has no [comfort] table")
    data["comfort"] = dict(spec.weights)  # by the standard terms' names, in the registry's order
    data["floor"] = dict(enabled=spec.floor)
    data["self_collision"] = dict(enabled=spec.self_collision)
    if spec.obstacles:
        data["obstacles"] = [obstacle_table(ob) for ob in spec.obstacles]
    if start is not None:
        joints = {n: float(v) for n, v in zip(model.joint_names, start[: model.n], strict=True) if abs(v) > 1e-12}
        if joints:
            data["start"] = {"joints": joints}
    data["targets"] = [_target_table(t) for t in spec.targets]
    data["loads"] = [dict(tcp=ld.tcp, force=floats(ld.force)) for ld in spec.loads]
    data["loops"] = [_loop_table(lp) for lp in spec.loops]
    if carried is not None:
        data["carried"] = dict(name=carried.name, size=floats(carried.size), tcps=list(carried.tcps))
    return {k: v for k, v in data.items() if v != []}


def dumps_scenario(data: dict) -> str:
    """TOML text of a scenario dict (from :func:`scenario_to_dict`); ``load_scenario`` reads it back."""
    return dumps_toml(data, ScenarioError)


def write_scenario(path: str | Path, data: dict, inline: bool = False) -> Path:
    """Write the scenario dict ``data`` as a TOML file, its mesh obstacles as OBJ files beside it (all atomically,
    the TOML last); ``inline`` (or ``path`` "-", standard output) keeps the meshes in the TOML. The TOML's path."""
    return write_scenario_files(path, data, inline)[-1]


def write_scenario_files(path: str | Path, data: dict, inline: bool = False) -> list[Path]:
    """:func:`write_scenario`, returning every file written: the mesh files, then the TOML."""
    if inline or str(path) == STDOUT:
        return [Path(write_text(path, dumps_scenario(data)))]
    path = Path(path)
    tables, meshes = mesh_files(path, data.get("obstacles", []))
    text = dumps_scenario({**data, "obstacles": tables} if tables else data)  # checked before anything is written
    return write_texts([*meshes, (path, text)])


def _relaxation(table: dict, lock: tuple[str, ...], operator: np.ndarray | None) -> None:
    if operator is None:
        table["lock"] = list(lock)
    else:
        table["operator"] = [floats(row) for row in np.asarray(operator, dtype=float)]


def _target_table(t: Target) -> dict:
    table: dict[str, Any] = dict(tcp=t.tcp, position=floats(t.position))
    if t.rotation is not None:
        table["rotation"] = quaternion(t.rotation)
    _relaxation(table, t.lock, t.operator)
    table.update(weight=float(t.weight), support=bool(t.support), friction=float(t.friction), enabled=bool(t.enabled))
    if t.sole is not None:
        table["sole"] = [floats(p) for p in np.asarray(t.sole, dtype=float)]
    if t.priority is not None:
        table["priority"] = int(t.priority)
    return table


def _loop_table(lp: Loop) -> dict:
    table: dict[str, Any] = dict(tcp=lp.tcp, other=lp.other, offset_position=floats(lp.offset_position))
    if lp.offset_rotation is not None:
        table["offset_rotation"] = quaternion(lp.offset_rotation)
    _relaxation(table, lp.lock, lp.operator)
    table["weight"] = float(lp.weight)
    return table
