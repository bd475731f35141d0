"""Obstacles in scenario files: ``[[obstacles]]`` tables read into shapes and shapes written back (m, world frame).

    [[obstacles]]
    name = "shelf"
    kind = "box"              # box (center, size, rotation), sphere (center, radius), capsule (a, b, radius),
    center = [0.0, -0.6, 0.8] # plane (point, normal: the free side), mesh (file = "shelf.obj" beside the
    size = [1.0, 0.4, 0.02]   # scenario, .obj/.stl/.ply, or inline vertices and faces)
    clearance = 0.01          # m the body keeps from it (default 0)

The kinds and their keys are the registry's (:data:`solver.collision.KINDS`): each kind's ``keys`` say what its
table holds, read and written here by what each key holds (a point, a length, a rotation...).

:func:`obstacle_table` writes a mesh inline (its vertices and faces); ``write_scenario`` moves it into an OBJ file
beside the scenario (:mod:`.obstacle_files`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...collision import KINDS, Obstacle
from ...collision.kinds.base import INDICES, LENGTH, POINT, POINTS, ROTATION, VECTOR
from ...errors import ScenarioError
from ...problem.specs import MAX_DISTANCE
from ..table_reader import TableReader
from ..values import floats, quaternion

LIMIT = MAX_DISTANCE  # m: coordinates and sizes within this, as targets
COMMON = {"kind", "name", "clearance"}  # every kind's keys, and its own (its ``keys``)

# How a kind's key of each type is read (None: not given, the shape's default) and written.
READ = {
    POINT: lambda t, key: t.vector(key, 3, limit=LIMIT),
    VECTOR: lambda t, key: t.vector(key, 3, limit=LIMIT),
    LENGTH: lambda t, key: t.positive(key, LIMIT, "m"),
    ROTATION: lambda t, key: t.rotation(key),
    POINTS: lambda t, key: (t.required(key), t.points(key, 3, "a list of [x, y, z] corners, m"))[1],
    INDICES: lambda t, key: (t.required(key), t.get(key))[1],
}
WRITE = {
    POINT: floats,
    VECTOR: floats,
    LENGTH: float,
    ROTATION: quaternion,
    POINTS: lambda points: [floats(p) for p in points],
    INDICES: lambda indices: np.asarray(indices).tolist(),
}


def kind_keys(kind: str) -> set[str]:
    """The keys an ``[[obstacles]]`` table of ``kind`` may hold."""
    shape = KINDS[kind]
    return COMMON | set(shape.keys) | ({"file"} if shape.files else set())


def read_obstacles(tables: list[TableReader], folder: Path) -> list[Obstacle]:
    """The shapes of ``[[obstacles]]``; a mesh ``file`` is relative to ``folder`` (the scenario's)."""
    out = []
    for index, t in enumerate(tables):
        kind = t.choice("kind", KINDS, "the kind of obstacle")
        t.known(kind_keys(kind))
        common = dict(name=t.string("name", f"obstacle {index + 1}"), clearance=t.number("clearance", 0.0, 0.0, 10.0))
        try:
            out.append(_shape(t, kind, folder, common))
        except ScenarioError as exc:  # the shape's own check: say which file it is in
            message = str(exc)
            raise ScenarioError(message if message.startswith(str(t.path)) else f"{t.path}: {message}") from None
    names = [ob.name for ob in out]
    for later, name in enumerate(names):
        first = names.index(name)
        if first < later:
            raise tables[later].fail("name", f"a name not used by obstacles[{first}]", name)
    return out


def _shape(t: TableReader, kind: str, folder: Path, common: dict) -> Obstacle:
    """One shape of ``kind`` from its table, key by key as its ``keys`` say (the shapes check their own geometry)."""
    shape = KINDS[kind]
    if shape.files and "file" in t.data:
        if any(key in t.data for key in shape.keys):
            raise t.fail("file", f"either a {kind} file or inline {' and '.join(shape.keys)}, not both")
        return shape.from_file(folder / t.string("file"), **common)
    values = {key: READ[what](t, key) for key, what in shape.keys.items()}
    return shape(**{key: value for key, value in values.items() if value is not None}, **common)


def obstacle_table(ob: Obstacle) -> dict:
    """An obstacle as the ``[[obstacles]]`` table :func:`read_obstacles` reads."""
    table: dict = dict(name=ob.name, kind=ob.kind)
    table.update({key: WRITE[what](getattr(ob, key)) for key, what in ob.keys.items()})
    table["clearance"] = float(ob.clearance)
    return table
