"""An independent check of a result file's collisions (issue 20): distances recomputed from the result JSON's
``collision_shapes`` and the scenario's ``[[obstacles]]`` and ``[floor]`` alone, without ``solver.collision``.

Deliberately plain methods, each obviously right rather than fast:

- The distance from a point moving along a capsule's axis p(t) = p0 + t (p1 - p0) to a convex set (a box, a
  segment, a triangle) is a convex function of t, and so is the *signed* distance to a convex solid (a supremum of
  affine functions). Its minimum over t in [0, 1] is found by golden-section search (the interval shrinks to
  1e-15 of the axis), then compared with both ends.
- Spheres and planes in closed form; a cylinder as a rectangle turned about its axis: a point's signed distance to
  it is that of (its distance from the axis, its place along it) to the rectangle [-R, R] x [0, L] (the point's own
  side of the axis holds the nearest side), measured with the box's formula; a mesh as the minimum over its
  triangles (point-triangle: the plane when the projection falls inside, else the nearest of the three edges), with
  a bounding-ball cull that drops only triangles that cannot be the nearest; inside a closed mesh by the generalised
  winding number (solid angles).
- A carried box (a frame's ``carried`` entry) is placed again from the frame's own TCP positions (centre their
  midpoint, x from the first to the second, z world up made square to x, or world y for a near-vertical x), checked
  against the centre and rotation the file states, and then measured like any box, leaving out the capsules on the
  two holding TCPs' links (the hands holding it). It is kept out of the obstacles and above the floor too: its 12
  edges measured against each obstacle, and a box's edges, a capsule's axis, a sphere's centre or a mesh's edges
  against it (the signed distance to the box along each segment: a mesh edge through the box with both its ends
  outside, or a mesh corner poking into the middle of a face, is inside). A cylinder's edges are its two rims,
  measured as RIM chords each: inside the rim by at most R (1 - cos(pi / RIM)) < 3e-7 R.
- Penetration is the depth of the deepest point of the capsule's axis inside the obstacle plus the radius, so the
  measured "distance" is negative whenever the capsule and the obstacle overlap; where they are apart it is the
  exact surface-to-surface distance. (For a box the solver reports the shortest separating translation instead,
  which is never smaller: only non-negative distances are compared with the solver's.)

Units: metres. Meshes: inline ``vertices``/``faces`` or an OBJ ``file`` beside the scenario.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np

GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0
STEPS = 72  # golden-section steps: 0.618^72 < 1e-15
SAMPLES = 33  # axis samples tested for being inside a closed mesh
TOLERANCE = 1e-3  # m: the solver's clearance rows count as met this far inside
AGREE = 1e-6  # m: a reported distance or point agrees with the recomputed one
CONTACT = 0.01  # m: a capsule this near an obstacle's clearance must be among the frame's closest pairs
RIM = 4096  # chords along each rim of a cylinder measured against a carried box


def dot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    return np.sum(x * y, axis=-1)


def quaternion_matrix(q) -> np.ndarray:
    """Rotation matrix of the quaternion [w, x, y, z] (normalised here)."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def point_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance (...) from points p to segments a-b, all (..., 3) broadcast together."""
    u = b - a
    t = np.clip(dot(p - a, u) / np.maximum(dot(u, u), 1e-300), 0.0, 1.0)
    return np.linalg.norm(p - a - t[..., None] * u, axis=-1)


def point_box(p: np.ndarray, center, size, rotation: np.ndarray) -> np.ndarray:
    """Signed distance (...) from points p to a box (negative inside: minus the distance to the nearest face)."""
    local = (p - np.asarray(center, dtype=float)) @ rotation
    q = np.abs(local) - 0.5 * np.asarray(size, dtype=float)
    return np.linalg.norm(np.maximum(q, 0.0), axis=-1) + np.minimum(q.max(axis=-1), 0.0)


def point_cylinder(p: np.ndarray, a, b, radius: float) -> np.ndarray:
    """Signed distance (...) from points p to a solid cylinder of ``radius`` with end centres a, b (module docstring):
    the rectangle in the (off-axis, along-axis) plane as a box with no third side."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    length = float(np.linalg.norm(b - a))
    u = (b - a) / length
    along_axis = dot(p - a, u)
    off_axis = np.linalg.norm(p - a - along_axis[..., None] * u, axis=-1)
    plane = np.stack([off_axis, along_axis, np.zeros_like(off_axis)], axis=-1)
    return point_box(plane, [0.0, length / 2.0, 0.0], [2.0 * radius, length, 1e9], np.eye(3))


def cylinder_rims(ob: dict) -> tuple[np.ndarray, np.ndarray]:
    """The RIM chords (starts, ends (2 RIM, 3) m) of each rim of a cylinder table, corners on the rims."""
    a, b = np.asarray(ob["a"], dtype=float), np.asarray(ob["b"], dtype=float)
    u = (b - a) / np.linalg.norm(b - a)
    x = np.cross(u, [1.0, 0.0, 0.0] if abs(u[0]) < 0.9 else [0.0, 1.0, 0.0])
    x /= np.linalg.norm(x)
    angle = np.linspace(0.0, 2.0 * math.pi, RIM + 1)[:, None]
    ring = ob["radius"] * (np.cos(angle) * x + np.sin(angle) * np.cross(u, x))
    return np.concatenate([a + ring[:-1], b + ring[:-1]]), np.concatenate([a + ring[1:], b + ring[1:]])


def point_triangle(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Distance (...) from points p to triangles a, b, c (broadcast): |height| when the projection falls inside,
    else the nearest edge."""
    n = np.cross(b - a, c - a)
    length = np.linalg.norm(n, axis=-1)
    unit = n / np.maximum(length, 1e-300)[..., None]
    height = dot(p - a, unit)
    q = p - height[..., None] * unit
    inside = length > 1e-300
    for x, y in ((a, b), (b, c), (c, a)):
        inside = inside & (dot(np.cross(y - x, q - x), n) >= 0.0)
    edges = np.minimum(np.minimum(point_segment(p, a, b), point_segment(p, b, c)), point_segment(p, c, a))
    return np.where(inside, np.abs(height), edges)


def winding(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Generalised winding number (m,) of points (m, 3) for triangles (F, 3, 3): +-1 inside a closed mesh, 0 out
    (the sum of the triangles' solid angles seen from the point, over 4 pi)."""
    out = np.empty(len(points))
    for i in range(len(points)):
        a, b, c = (triangles[:, j] - points[i] for j in range(3))
        la, lb, lc = (np.linalg.norm(v, axis=-1) for v in (a, b, c))
        numerator = dot(a, np.cross(b, c))
        denominator = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la
        out[i] = np.sum(2.0 * np.arctan2(numerator, denominator)) / (4.0 * math.pi)
    return out


def minimise_convex(f, shape: tuple[int, ...]) -> np.ndarray:
    """min over t in [0, 1] of f(t), f convex in t, elementwise over arrays of ``shape``: golden-section search."""
    lo, hi = np.zeros(shape), np.ones(shape)
    for _ in range(STEPS):
        a, b = hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo)
        left = f(a) <= f(b)  # a minimiser lies in [lo, b]
        hi, lo = np.where(left, b, hi), np.where(left, lo, a)
    ends = [f(np.zeros(shape)), f(np.ones(shape)), f(lo), f(hi)]
    return np.minimum.reduce(ends)


def along(p0: np.ndarray, p1: np.ndarray):
    """The axis point p(t) for t (k,) (or (k, F), the axis repeated per triangle)."""
    return lambda t: p0 + t[..., None] * (p1 - p0)


def is_closed(faces: np.ndarray) -> bool:
    """Every edge used once in each direction (watertight, consistently oriented)."""
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    forward = {tuple(e) for e in directed.tolist()}
    return len(forward) == len(directed) and all((b, a) in forward for a, b in forward)


def mesh_axis_distance(p0: np.ndarray, p1: np.ndarray, mesh: dict) -> np.ndarray:
    """Signed distance (k,) from capsule axes to a mesh: the exact axis-to-surface distance, or for a closed mesh
    minus the deepest inside axis sample's depth when any sample is inside."""
    tris = mesh["triangles"]
    centre = tris.mean(axis=1)
    reach = np.linalg.norm(tris - centre[:, None], axis=-1).max(axis=1)
    lower = point_segment(centre[None], p0[:, None], p1[:, None]) - reach  # (k, F): no triangle point is nearer
    upper = point_segment(tris[None, :, 0], p0[:, None], p1[:, None]).min(axis=1)  # a corner: at most this far
    cap, tri = np.nonzero(lower <= upper[:, None])  # the (capsule, triangle) pairs that may be the nearest
    a, b, c = (tris[tri, i] for i in range(3))
    pair = minimise_convex(lambda t: point_triangle(along(p0[cap], p1[cap])(t), a, b, c), (len(cap),))
    out = np.full(len(p0), np.inf)
    np.minimum.at(out, cap, pair)
    if mesh["closed"]:
        samples = (p0[:, None] + np.linspace(0.0, 1.0, SAMPLES)[None, :, None] * (p1 - p0)[:, None]).reshape(-1, 3)
        inside = np.abs(winding(samples, tris)) > 0.5
        depth = np.zeros(len(samples))
        for i in np.flatnonzero(inside):
            depth[i] = point_triangle(samples[i], tris[:, 0], tris[:, 1], tris[:, 2]).min()
        deepest, entered = depth.reshape(len(p0), -1).max(axis=1), inside.reshape(len(p0), -1).any(axis=1)
        out = np.where(entered, -deepest, out)
    return out


def axis_distance(ob: dict, p0: np.ndarray, p1: np.ndarray) -> np.ndarray:
    """Signed distance (k,) from capsule axes p0-p1 (k, 3) to an obstacle table (the capsule's radius not taken)."""
    kind, k = ob["kind"], (len(p0),)
    if kind == "plane":
        n = np.asarray(ob["normal"], dtype=float) / np.linalg.norm(ob["normal"])
        return np.minimum((p0 - ob["point"]) @ n, (p1 - ob["point"]) @ n)
    if kind == "sphere":
        return point_segment(np.asarray(ob["center"], dtype=float), p0, p1) - ob["radius"]
    if kind == "capsule":
        a, b = np.asarray(ob["a"], dtype=float), np.asarray(ob["b"], dtype=float)
        return minimise_convex(lambda t: point_segment(along(p0, p1)(t), a, b), k) - ob["radius"]
    if kind == "box":
        rotation = _box_rotation(ob)
        return minimise_convex(lambda t: point_box(along(p0, p1)(t), ob["center"], ob["size"], rotation), k)
    if kind == "cylinder":
        return minimise_convex(lambda t: point_cylinder(along(p0, p1)(t), ob["a"], ob["b"], ob["radius"]), k)
    if kind == "mesh":
        return mesh_axis_distance(p0, p1, ob)
    raise ValueError(f"unknown obstacle kind {kind!r}")


def surface_distance(ob: dict, point: np.ndarray) -> float:
    """Unsigned distance (m) from a point to an obstacle's surface."""
    kind = ob["kind"]
    if kind == "mesh":
        tris = ob["triangles"]
        return float(point_triangle(point, tris[:, 0], tris[:, 1], tris[:, 2]).min())
    if kind == "box":
        rotation = _box_rotation(ob)
        return abs(float(point_box(point, ob["center"], ob["size"], rotation)))
    return abs(float(axis_distance(ob, point[None], point[None])[0]))


def capsule_pair(a0, a1, b0, b1) -> float:
    """Distance (m) between the axes a0-a1 and b0-b1."""
    a0, a1, b0, b1 = (np.asarray(v, dtype=float)[None] for v in (a0, a1, b0, b1))
    return float(minimise_convex(lambda t: point_segment(along(a0, a1)(t), b0, b1), (1,))[0])


def read_obj(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and (fan-triangulated) faces of an OBJ file; indices may be negative or carry /texture/normal."""
    vertices, faces = [], []
    for line in path.read_text(encoding="utf-8").splitlines():
        words = line.split()
        if words and words[0] == "v":
            vertices.append([float(w) for w in words[1:4]])
        elif words and words[0] == "f":
            ids = [int(w.split("/")[0]) for w in words[1:]]
            ids = [i - 1 if i > 0 else len(vertices) + i for i in ids]
            faces += [[ids[0], ids[i], ids[i + 1]] for i in range(1, len(ids) - 1)]
    return np.array(vertices, dtype=float), np.array(faces, dtype=int)


def scenario_obstacles(path: str | Path) -> tuple[list[dict], bool]:
    """The scenario's ``[[obstacles]]`` tables (names and clearances defaulted, meshes loaded with their triangles
    and whether they are closed) and whether its floor is on (``[floor] enabled``, default true)."""
    path = Path(path)
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    out = []
    for i, table in enumerate(data.get("obstacles", [])):
        ob = dict(table, name=table.get("name", f"obstacle {i + 1}"), clearance=float(table.get("clearance", 0.0)))
        if ob["kind"] == "mesh":
            if "file" in ob:
                vertices, faces = read_obj(path.parent / ob["file"])
            else:
                vertices, faces = np.asarray(ob["vertices"], dtype=float), np.asarray(ob["faces"], dtype=int)
            ob.update(triangles=vertices[faces], closed=is_closed(faces))
        out.append(ob)
    return out, bool(data.get("floor", {}).get("enabled", True))


def carried_obstacle(frame: dict) -> tuple[dict, set[str], list[str]]:
    """The frame's carried box as a box obstacle table placed from its TCPs, the links it leaves out (the holding
    TCPs') and the disagreements with the centre and rotation the file states."""
    entry, tcps = frame["carried"], frame["tcps"]
    first, second = (np.asarray(tcps[name]["position"], dtype=float) for name in entry["tcps"])
    x = (second - first) / np.linalg.norm(second - first)
    up = np.array([0.0, 0.0, 1.0]) if abs(x[2]) < 0.99 else np.array([0.0, 1.0, 0.0])
    z = up - (up @ x) * x
    z /= np.linalg.norm(z)
    rotation = np.column_stack([x, np.cross(z, x), z])
    centre = (first + second) / 2.0
    stated = quaternion_matrix(entry["rotation"])
    out = []
    for what, error in (("center", np.abs(np.subtract(entry["center"], centre)).max()),
                        ("rotation", np.abs(stated - rotation).max())):  # fmt: skip
        if error > AGREE:
            out.append(f"frame {frame['frame']}: carried {entry['name']!r}: {what} off by {error:.3g} (vs its TCPs)")
    box = dict(kind="box", name=entry["name"], center=centre.tolist(), size=entry["size"], rotation_matrix=rotation,
               clearance=float(entry["clearance"]))  # fmt: skip
    return box, {tcps[name]["link"] for name in entry["tcps"]}, out


def box_edges(ob: dict) -> tuple[np.ndarray, np.ndarray]:
    """The 12 edges (starts, ends (12, 3) m) of a box table."""
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
    world = np.asarray(ob["center"]) + (corners * np.asarray(ob["size"]) / 2.0) @ _box_rotation(ob).T
    pairs = [(i, j) for i in range(8) for j in range(i + 1, 8) if np.abs(corners[i] - corners[j]).sum() == 2]
    return world[[i for i, _ in pairs]], world[[j for _, j in pairs]]


def carried_distance(box: dict, ob: dict) -> float:
    """Signed distance (m) between a carried box and an obstacle: the least over the box's edges to the obstacle and
    the obstacle's edges (its axis, its centre, a cylinder's rims; every triangle's edges of a mesh) to the box (two
    convex shapes are nearest at an edge of one of them)."""
    a, b = box_edges(box)
    distance = float(axis_distance(ob, a, b).min())
    kind = ob["kind"]
    if kind == "box":
        a, b = box_edges(ob)
        distance = min(distance, float(axis_distance(box, a, b).min()))
    elif kind == "cylinder":
        a, b = cylinder_rims(ob)
        distance = min(distance, float(axis_distance(box, a, b).min()))
    elif kind in ("capsule", "sphere"):
        a, b = (ob["a"], ob["b"]) if kind == "capsule" else (ob["center"], ob["center"])
        distance = min(
            distance, float(axis_distance(box, np.array([a], float), np.array([b], float))[0]) - ob["radius"]
        )
    elif kind == "mesh":
        tris = ob["triangles"]
        a, b = tris.reshape(-1, 3), tris[:, [1, 2, 0]].reshape(-1, 3)  # the triangles' edges (shared ones twice)
        # the box lies in the ball about its centre of radius half its diagonal, so no point p of an edge is nearer
        # (signed) than |p - centre| - that radius: the edges for which that bound is not below the least so far
        # cannot lower it
        reach = float(np.linalg.norm(box["size"])) / 2.0
        maybe = point_segment(np.asarray(box["center"], dtype=float), a, b) - reach <= distance
        if maybe.any():
            distance = min(distance, float(axis_distance(box, a[maybe], b[maybe]).min()))
    return distance


def _carried_problems(frame: dict, box: dict, others: list[dict], tolerance: float) -> list[str]:
    """The carried box inside an obstacle's clearance or below the floor by more than ``tolerance``; its closest
    entries against the recomputed distance and surfaces; an obstacle within CONTACT of it missing from them."""
    out, number = [], frame["frame"]
    listed = {entry["other"]: entry for entry in frame.get("closest", []) if entry["part"] == box["name"]}
    for ob in others:
        distance = carried_distance(box, ob)
        if distance < ob["clearance"] - tolerance:
            out.append(f"frame {number}: {box['name']} vs {ob['name']}: {distance:.4f} m, clearance {ob['clearance']}")
        entry = listed.get(ob["name"])
        if entry is not None:
            on_box = abs(float(point_box(np.asarray(entry["point"]), box["center"], box["size"], _box_rotation(box))))
            out += _reported(frame, entry, distance, surface_distance(ob, np.asarray(entry["other_point"])), on_box)
        elif distance < ob["clearance"] + CONTACT:
            out.append(f"frame {number}: {box['name']} vs {ob['name']} at {distance:.4f} m: not in closest")
    return out


def _box_rotation(ob: dict) -> np.ndarray:
    """A box table's rotation matrix: given as one (a carried box) or as a quaternion (default none)."""
    if "rotation_matrix" in ob:
        return np.asarray(ob["rotation_matrix"], dtype=float)
    return quaternion_matrix(ob.get("rotation", [1.0, 0.0, 0.0, 0.0]))


def _shapes(frame: dict) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
    shapes = frame["collision_shapes"]
    names = [s["link"] for s in shapes]
    p0, p1 = (np.array([s[key] for s in shapes], dtype=float).reshape(-1, 3) for key in ("start", "end"))
    return names, p0, p1, np.array([s["radius"] for s in shapes], dtype=float)


def _reported(frame: dict, entry: dict, distance: float, other_surface: float, part_surface: float) -> list[str]:
    """Disagreements between a closest entry and the recomputed distance and surfaces (apart pairs only)."""
    if distance < 0.0 or entry["distance"] < 0.0:
        return []
    gap = float(np.linalg.norm(np.subtract(entry["point"], entry["other_point"])))
    out = []
    for what, error in (("distance", entry["distance"] - distance), ("|point - other_point| - distance",
                        gap - distance), ("other_point off the other's surface by", other_surface),
                        ("point off the part's surface by", part_surface)):  # fmt: skip
        if abs(error) > AGREE:
            out.append(f"frame {frame['frame']}: {entry['pair']}: {what} {error:+.3g} m (reported vs recomputed)")
    return out


def frame_problems(frame: dict, obstacles: list[dict], floor: bool, tolerance: float = TOLERANCE) -> list[str]:
    """Everything wrong with one result frame: a capsule below the floor, inside an obstacle's clearance or
    overlapping another body part (a pair in ``closest``) by more than ``tolerance``; a closest entry whose
    distance or points disagree with the recomputed ones; an obstacle in contact missing from ``closest``; a carried
    box (the frame's ``carried``) placed elsewhere than between its TCPs, or with a body part but the holding hands in
    it."""
    names, p0, p1, radius = _shapes(frame)
    link = {n: i for i, n in enumerate(names)}
    out, number = [], frame["frame"]
    held: dict[str, np.ndarray] = {}  # per obstacle, the capsules it leaves out: a carried box's holding hands
    planes = [dict(kind="plane", name="floor", point=[0, 0, 0], normal=[0, 0, 1], clearance=0.0)] if floor else []
    if "carried" in frame:
        box, holding, wrong = carried_obstacle(frame)
        out += wrong + _carried_problems(frame, box, [*obstacles, *planes], tolerance)
        obstacles = [*obstacles, box]
        held[box["name"]] = np.isin(names, list(holding))
    others = list(obstacles) + planes
    distances = {}
    for ob in others:
        distance = axis_distance(ob, p0, p1) - radius
        distance[held.get(ob["name"], np.zeros(len(names), dtype=bool))] = np.inf
        distances[ob["name"]] = distance
        for i in np.flatnonzero(distance < ob["clearance"] - tolerance):
            out.append(f"frame {number}: {names[i]} vs {ob['name']}: {distance[i]:.4f} m, clearance {ob['clearance']}")
    by_name = {ob["name"]: ob for ob in others}
    listed = set()
    carried = frame.get("carried", {}).get("name")
    for entry in frame.get("closest", []):
        part, other = entry["part"], entry["other"]
        listed.add((part, other))
        if part == carried:
            continue  # the carried box against an obstacle: checked above
        if other in by_name:
            name, _, end = part.rpartition(".") if part.endswith((".start", ".end")) else (part, "", "")
            i = link[name]
            ends = {"start": p0[i], "end": p1[i]}
            a, b = (ends[end], ends[end]) if end else (p0[i], p1[i])
            distance = float(axis_distance(by_name[other], a[None], b[None])[0]) - radius[i]
            own = point_segment(np.asarray(entry["point"]), a, b) - radius[i]
            out += _reported(frame, entry, distance, surface_distance(by_name[other], np.asarray(entry["other_point"])),
                             float(own))  # fmt: skip
        elif other in link:  # a pair of body parts: kept apart by the entry's clearance (negative if they overlap)
            i, j = link[part], link[other]
            distance = capsule_pair(p0[i], p1[i], p0[j], p1[j]) - radius[i] - radius[j]
            if distance < entry["clearance"] - tolerance:
                out.append(f"frame {number}: {part} vs {other}: {distance:.4f} m, clearance {entry['clearance']}")
            own = point_segment(np.asarray(entry["point"]), p0[i], p1[i]) - radius[i]
            theirs = point_segment(np.asarray(entry["other_point"]), p0[j], p1[j]) - radius[j]
            out += _reported(frame, entry, distance, float(theirs), float(own))
        else:
            out.append(f"frame {number}: closest entry {entry['pair']!r}: {other!r} is no obstacle and no body part")
    for ob in obstacles:  # the floor's rows leave out the supports' capsules: not checked for completeness
        for i in np.flatnonzero(distances[ob["name"]] < ob["clearance"] + CONTACT):
            if (names[i], ob["name"]) not in listed:
                out.append(
                    f"frame {number}: {names[i]} vs {ob['name']} at {distances[ob['name']][i]:.4f} m: not in closest"
                )
    return out


def non_finite(value, where: str = "") -> list[str]:
    """Paths of the NaN or infinite numbers in parsed JSON."""
    if isinstance(value, float):
        return [] if math.isfinite(value) else [where]
    if isinstance(value, dict):
        return [p for k, v in value.items() for p in non_finite(v, f"{where}.{k}")]
    if isinstance(value, list):
        return [p for i, v in enumerate(value) for p in non_finite(v, f"{where}[{i}]")]
    return []


def result_problems(document: dict, scenario: str | Path) -> list[str]:
    """:func:`frame_problems` of every frame of a parsed result JSON, the obstacles and floor from ``scenario``."""
    obstacles, floor = scenario_obstacles(scenario)
    return [p for frame in document["frames"] for p in frame_problems(frame, obstacles, floor)]
