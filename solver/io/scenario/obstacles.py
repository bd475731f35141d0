"""Obstacles in scenario files: ``[[obstacles]]`` tables read into shapes and shapes written back (m, world frame).

    [[obstacles]]
    name = "shelf"
    kind = "box"              # box (center, size, rotation), sphere (center, radius), capsule (a, b, radius),
    center = [0.0, -0.6, 0.8] # plane (point, normal: the free side), mesh (file = "shelf.obj" beside the
    size = [1.0, 0.4, 0.02]   # scenario, .obj/.stl/.ply, or inline vertices and faces)
    clearance = 0.01          # m the body keeps from it (default 0)

:func:`obstacle_table` writes a mesh inline (its vertices and faces); ``write_scenario`` moves it into an OBJ file
beside the scenario (:mod:`.obstacle_files`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...collision import Box, Capsule, HalfSpace, Mesh, Obstacle, Sphere, read_mesh
from ...errors import ScenarioError
from ...problem.specs import MAX_DISTANCE
from ..table_reader import TableReader
from ..values import floats, quaternion

KINDS = {"box": Box, "sphere": Sphere, "capsule": Capsule, "plane": HalfSpace, "mesh": Mesh}
KEYS = {
    "box": {"center", "size", "rotation"},
    "sphere": {"center", "radius"},
    "capsule": {"a", "b", "radius"},
    "plane": {"point", "normal"},
    "mesh": {"file", "vertices", "faces"},
}
LIMIT = MAX_DISTANCE  # m: coordinates and sizes within this, as targets


def read_obstacles(tables: list[TableReader], folder: Path) -> list[Obstacle]:
    """The shapes of ``[[obstacles]]``; a mesh ``file`` is relative to ``folder`` (the scenario's)."""
    out = []
    for index, t in enumerate(tables):
        kind = t.choice("kind", KINDS, "the kind of obstacle")
        t.known({"kind", "name", "clearance"} | KEYS[kind])
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
    """One shape of ``kind`` from its table (the shapes check their own geometry)."""
    if kind == "box":
        rotation = t.rotation("rotation")
        return Box(t.vector("center", 3, limit=LIMIT), t.vector("size", 3, limit=LIMIT),
                   np.eye(3) if rotation is None else rotation, **common)  # fmt: skip
    if kind == "sphere":
        return Sphere(t.vector("center", 3, limit=LIMIT), t.positive("radius", LIMIT, "m"), **common)
    if kind == "capsule":
        a, b = t.vector("a", 3, limit=LIMIT), t.vector("b", 3, limit=LIMIT)
        return Capsule(a, b, t.positive("radius", LIMIT, "m"), **common)
    if kind == "plane":
        return HalfSpace(t.vector("point", 3, limit=LIMIT), t.vector("normal", 3, limit=LIMIT), **common)
    if "file" in t.data:
        if "vertices" in t.data or "faces" in t.data:
            raise t.fail("file", "either a mesh file or inline vertices and faces, not both")
        return read_mesh(folder / t.string("file"), **common)
    t.required("vertices", "faces")
    return Mesh(t.points("vertices", 3, "a list of [x, y, z] corners, m"), t.get("faces"), **common)


def obstacle_table(ob: Obstacle) -> dict:
    """An obstacle as the ``[[obstacles]]`` table :func:`read_obstacles` reads."""
    table: dict = dict(name=ob.name)
    if isinstance(ob, Box):
        table.update(kind="box", center=floats(ob.center), size=floats(ob.size), rotation=quaternion(ob.rotation))
    elif isinstance(ob, Sphere):
        table.update(kind="sphere", center=floats(ob.center), radius=float(ob.radius))
    elif isinstance(ob, Capsule):
        table.update(kind="capsule", a=floats(ob.a), b=floats(ob.b), radius=float(ob.radius))
    elif isinstance(ob, HalfSpace):
        table.update(kind="plane", point=floats(ob.point), normal=floats(ob.normal))
    else:
        table.update(kind="mesh", vertices=[floats(v) for v in ob.vertices], faces=ob.faces.tolist())
    table["clearance"] = float(ob.clearance)
    return table
