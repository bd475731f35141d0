"""Obstacle shapes validate their geometry with one-line errors; meshes read from OBJ, STL and PLY files round trip;
closedness, orientation and the inside test of a mesh; a mesh's edges that may be nearest a box."""

from __future__ import annotations

import dataclasses
import struct

import numpy as np
import pytest

from solver.body.spatial import exp_so3
from solver.collision import (
    Box,
    Capsule,
    HalfSpace,
    Mesh,
    MeshIndex,
    Sphere,
    box_distance,
    degenerate_faces,
    read_mesh,
    write_obj,
)
from solver.collision.generate import box_mesh, height_field
from solver.collision.mesh_edges import MeshEdges
from solver.errors import ScenarioError


def one_line_error(make, *words: str) -> str:
    with pytest.raises(ScenarioError) as info:
        make()
    message = str(info.value)
    assert "\n" not in message
    for word in words:
        assert word in message, message
    return message


def test_bad_primitive_geometry_is_one_line_naming_the_shape_and_field():
    one_line_error(lambda: Sphere([0, np.nan, 0], 0.1, name="ball"), "sphere 'ball'", "center", "finite")
    one_line_error(lambda: Sphere([0, 0, 0], 0.0), "radius", "> 0")
    one_line_error(lambda: Sphere([0, 0], 0.1), "center", "shape 3")
    one_line_error(lambda: Capsule([0, 0, 0], [1, 0, 0], -1.0, name="bar"), "capsule 'bar'", "radius")
    one_line_error(lambda: Box([0, 0, 0], [1, 0, 1]), "size", "> 0")
    one_line_error(lambda: Box([0, 0, 0], [1, 1, 1], np.diag([1.0, 1.0, -1.0])), "rotation", "proper rotation")
    one_line_error(lambda: Box([0, 0, 0], [1, 1, 1], np.ones((3, 3))), "rotation")
    one_line_error(lambda: HalfSpace([0, 0, 0], [0, 0, 0], name="floor"), "halfspace 'floor'", "normal", "non-zero")
    one_line_error(lambda: Sphere([0, 0, 0], 0.1, clearance=-0.01), "clearance", ">= 0")
    one_line_error(lambda: Sphere("abc", 0.1), "center", "numbers")


def test_shapes_are_frozen_and_normalised():
    plane = HalfSpace([0, 0, 0], [0, 0, 2.0], name="floor", clearance=0.01)
    assert np.allclose(plane.normal, [0, 0, 1]) and plane.clearance == 0.01 and plane.name == "floor"
    with pytest.raises(dataclasses.FrozenInstanceError):
        plane.point = np.zeros(3)
    with pytest.raises(ValueError):
        plane.normal[0] = 1.0
    box = Box([0, 0, 0], [1, 2, 3])
    assert np.allclose(box.half, [0.5, 1, 1.5]) and np.allclose(box.rotation, np.eye(3))


def test_bad_meshes_are_one_line_naming_the_face():
    vertices, faces = box_mesh([0, 0, 0], [1, 1, 1])
    one_line_error(lambda: Mesh(vertices, faces + [0, 0, 100], name="m"), "mesh 'm'", "faces[0]", "out of range")
    flat = faces.copy()
    flat[3] = [0, 0, 1]
    one_line_error(lambda: Mesh(vertices, flat), "faces[3]", "degenerate")
    collinear = np.vstack([vertices, [[0, 0, 0], [1, 0, 0], [2, 0, 0]]])
    line = np.vstack([faces, [[8, 9, 10]]])
    one_line_error(lambda: Mesh(collinear, line), f"faces[{len(faces)}]", "degenerate")
    bad = vertices.copy()
    bad[2, 1] = np.inf
    one_line_error(lambda: Mesh(bad, faces), "vertices", "finite")
    one_line_error(lambda: Mesh(vertices, faces + 0.5), "faces", "integer")
    one_line_error(lambda: Mesh(vertices, np.zeros((0, 3), dtype=int)), "faces", "N >= 1")
    assert degenerate_faces(collinear, line).sum() == 1


def test_closed_means_every_edge_shared_by_two_faces_in_opposite_directions():
    vertices, faces = box_mesh([0, 0, 0], [1, 2, 3], 3)
    assert Mesh(vertices, faces).is_closed()
    assert Mesh(vertices, faces).signed_volume() == pytest.approx(6.0)
    assert Mesh(vertices, faces[:, ::-1]).is_closed()  # inside out, still consistent
    assert Mesh(vertices, faces[:, ::-1]).signed_volume() == pytest.approx(-6.0)
    assert not Mesh(vertices, faces[1:]).is_closed()  # a hole
    flipped = faces.copy()
    flipped[5] = flipped[5, ::-1]
    assert not Mesh(vertices, flipped).is_closed()  # one face the wrong way round
    assert not Mesh(vertices, np.vstack([faces, faces[:2]])).is_closed()  # an edge shared by four faces
    assert not Mesh(*height_field([0, 0, 0], [1, 1], (3, 3), lambda x, y: 0 * x)).is_closed()


@pytest.mark.parametrize("reverse", [False, True])
def test_inside_by_ray_parity_including_points_on_projected_edges_and_corners(reverse):
    vertices, faces = box_mesh([0, 0, 0], [1.0, 2.0, 3.0], 4)
    index = MeshIndex(Mesh(vertices, faces[:, ::-1] if reverse else faces))
    rng = np.random.default_rng(30)
    points = rng.uniform(-2, 2, (20000, 3))
    points[:8000] = np.round(points[:8000] * 8) / 8  # on the grid lines of the faces seen from below
    half = np.array([0.5, 1.0, 1.5])
    on_surface = np.any(np.isclose(np.abs(points), half), axis=1) & np.all(np.abs(points) <= half + 1e-12, axis=1)
    inside = np.all(np.abs(points) < half, axis=1)
    got = index.contains(points)
    assert inside.sum() > 1000
    assert np.array_equal(got[~on_surface], inside[~on_surface])
    outward = index.normals[np.argmax(index.centroid[:, 2])]  # a top face
    assert np.allclose(outward, [0, 0, 1])


def test_an_open_mesh_has_no_inside():
    index = MeshIndex(Mesh(*height_field([0, 0, 0], [1, 1], (3, 3), lambda x, y: 0 * x)))
    assert not index.closed
    assert not index.contains(np.array([[0.5, 0.5, -0.1], [0.5, 0.5, 0.1]])).any()


def triangles(mesh: Mesh) -> set:
    """The mesh's triangles as sets of rounded corner coordinates (independent of vertex numbering and start)."""
    return {frozenset(map(tuple, np.round(mesh.vertices[f], 6))) for f in mesh.faces}


def test_obj_round_trip_and_polygons_negative_indices_and_slashes(tmp_path):
    vertices, faces = box_mesh([0.1, 0.2, 0.3], [1, 2, 3], 2)
    write_obj(tmp_path / "box.obj", vertices, faces)
    mesh = read_mesh(tmp_path / "box.obj", name="box", clearance=0.02)
    assert np.allclose(mesh.vertices, vertices) and np.array_equal(mesh.faces, faces)
    assert mesh.name == "box" and mesh.clearance == 0.02 and mesh.is_closed()
    text = (
        "# a square and a triangle\nmtllib x.mtl\no quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\n"
        "f 1/1/1 2/2/1 3/3/1 4/4/1\nv 0 0 1\nf -1//1 -4//1 -5//1  # relative\n"
    )
    (tmp_path / "quad.obj").write_text(text)
    mesh = read_mesh(tmp_path / "quad.obj")
    assert mesh.name == "quad"
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3], [4, 1, 0]]


def write_binary_stl(path, vertices, faces) -> None:
    record = np.zeros(len(faces), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    record["v"] = vertices[faces]
    path.write_bytes(b"solid but binary".ljust(80, b" ") + struct.pack("<I", len(faces)) + record.tobytes())


def write_ascii_stl(path, vertices, faces) -> None:
    lines = ["solid box"]
    for f in faces:
        lines += ["facet normal 0 0 0", " outer loop"]
        lines += [f"  vertex {x:.9g} {y:.9g} {z:.9g}" for x, y, z in vertices[f]]
        lines += [" endloop", "endfacet"]
    path.write_text("\n".join(lines + ["endsolid box"]) + "\n")


@pytest.mark.parametrize("writer", [write_binary_stl, write_ascii_stl])
def test_stl_round_trip_welds_corners_into_a_closed_mesh(tmp_path, writer):
    vertices, faces = box_mesh([0.0, 0.5, 1.0], [1, 2, 0.5], 3)
    writer(tmp_path / "box.stl", vertices, faces)
    mesh = read_mesh(tmp_path / "box.stl")
    assert len(mesh.vertices) == len(vertices) and len(mesh.faces) == len(faces)
    assert triangles(mesh) == triangles(Mesh(vertices, faces))
    assert mesh.is_closed() and mesh.signed_volume() == pytest.approx(1.0, rel=1e-6)


def write_ply(path, vertices, faces, binary: bool) -> None:
    quads = np.column_stack([faces[0::2], faces[1::2, 2]])  # box_mesh's triangle pairs back into squares
    header = [
        "ply",
        f"format {'binary_little_endian' if binary else 'ascii'} 1.0",
        "comment made by a test",
        f"element vertex {len(vertices)}",
        "property float x",
        "property float y",
        "property float z",
        "property uchar red",
        f"element face {len(quads)}",
        "property list uchar int vertex_indices",
        "end_header",
    ]
    head = ("\n".join(header) + "\n").encode()
    if binary:
        table = np.zeros(len(vertices), dtype=[("p", "<f4", 3), ("r", "u1")])
        table["p"] = vertices
        body = table.tobytes() + b"".join(struct.pack("<B4i", 4, *q) for q in quads)
    else:
        body = "".join(f"{x} {y} {z} 255\n" for x, y, z in vertices) + "".join(
            f"4 {a} {b} {c} {d}\n" for a, b, c, d in quads
        )
        body = body.encode()
    path.write_bytes(head + body)


@pytest.mark.parametrize("binary", [False, True])
def test_ply_round_trip_with_square_faces(tmp_path, binary):
    vertices, faces = box_mesh([0, 0, 0], [1, 1, 1], 2)
    write_ply(tmp_path / "box.ply", vertices, faces, binary)
    mesh = read_mesh(tmp_path / "box.ply")
    assert np.allclose(mesh.vertices, vertices)
    assert triangles(mesh) == triangles(Mesh(vertices, faces)) and mesh.is_closed()


def test_bad_mesh_files_are_one_line_naming_the_file_and_line(tmp_path):
    def bad(name: str, content: str | bytes, *words: str) -> None:
        path = tmp_path / name
        path.write_bytes(content if isinstance(content, bytes) else content.encode())
        one_line_error(lambda: read_mesh(path), name, *words)

    bad("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "line 4", "out of range")
    bad("b.obj", "v 0 0 0\nv 1 0 x\n", "line 2", "v x y z")
    bad("c.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", "line 3", "at least 3")
    bad("d.obj", "v 0 0 0\n", "no faces")
    bad("e.obj", "# a comment\nv 0 0 0\nv 1 0 0\nv 2 0 0\n\nf 1 2 3\n", "line 6", "degenerate")
    bad("e2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 0\nf 1 2 3\n", "line 4", "finite")
    bad("f.stl", b"\x00" * 90, "not an STL")
    bad("g.stl", "solid x\nfacet\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n", "line 6", "3 vertices")
    bad("h.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n", "element face")
    header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    bad("i.ply", header + "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n", "ends before")
    bad("j.mesh", "", "unknown mesh file type", ".obj")
    one_line_error(lambda: read_mesh(tmp_path / "missing.obj"), "missing.obj", "cannot read")


def test_a_mesh_keeps_its_edges_once_but_the_flat_ones_and_joins_straight_runs():
    """A box of 6 faces split into d x d squares keeps just its 12 edges, each one segment corner to corner (every edge
    inside a face is flat, the d pieces of a rim run straight); two coplanar triangles drop their shared edge, a fin
    (the second folded onto the first) keeps it."""
    turn = exp_so3(np.array([0.3, -0.2, 0.5]))
    for d in (1, 2, 5):
        edges = MeshIndex(Mesh(*box_mesh([0.1, 0.2, 0.3], [1.0, 0.5, 0.9], d, turn))).edges()
        local = np.abs((np.stack([edges.start, edges.end]) - [0.1, 0.2, 0.3]) @ turn)
        assert len(edges) == 12 and np.allclose(local, [0.5, 0.25, 0.45])  # corners
        lengths = np.linalg.norm(edges.end - edges.start, axis=1)
        np.testing.assert_allclose(np.sort(lengths), np.repeat([0.5, 0.9, 1.0], 4))
    square = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.5, -0.8, 0]], dtype=float)
    assert len(MeshEdges(square, np.array([[0, 1, 2], [1, 0, 3]]))) == 4
    fin = square * [[1, 1, 1], [1, 1, 1], [1, 1, 1], [1, -1, 1]]  # the second's far corner on the first's side
    assert len(MeshEdges(fin, np.array([[0, 1, 2], [1, 0, 3]]))) == 5
    assert len(MeshEdges(fin, np.array([[0, 1, 2], [0, 1, 3]]))) == 5  # either winding


@pytest.mark.parametrize("seed", range(3))
def test_the_edges_near_a_box_hold_the_nearest(seed):
    """Against every edge measured (box_distance): the edges whose bounds meet a box's are found by the tree, and the
    few near_box keeps hold the 8 nearest (their 8 least distances equal the 8 least of all), for a bumpy surface
    and a closed box of triangles, boxes turned at random through, on and near them."""
    rng = np.random.default_rng(seed)
    bumps = height_field([-0.5, -0.5, 0.0], [1.0, 1.0], (24, 24), lambda x, y: 0.05 * np.sin(9 * x) * np.cos(7 * y))
    meshes = [Mesh(*bumps), Mesh(*box_mesh([0.0, 0.0, -0.2], [0.8, 0.6, 0.4], 6, exp_so3(rng.normal(size=3))))]
    for mesh in meshes:
        edges = MeshIndex(mesh).edges()
        for _ in range(10):
            centre, turn = rng.uniform([-0.3, -0.3, -0.1], [0.3, 0.3, 0.3]), exp_so3(rng.normal(size=3))
            half = rng.uniform(0.05, 0.2, 3)
            low, high = centre - np.abs(turn) @ half - 0.05, centre + np.abs(turn) @ half + 0.05
            meet = np.flatnonzero(np.all((np.minimum(edges.start, edges.end) <= high)
                                         & (np.maximum(edges.start, edges.end) >= low), axis=1))  # fmt: skip
            assert np.array_equal(edges.meeting(low, high), meet)
            box = Box(centre, 2 * half, turn)
            every = box_distance(edges.start[meet], edges.end[meet], np.zeros(len(meet)), box).distance
            kept = edges.near_box(centre, turn, half, 0.05, 8)
            assert set(kept) <= set(meet)
            mine = box_distance(edges.start[kept], edges.end[kept], np.zeros(len(kept)), box).distance
            np.testing.assert_allclose(np.sort(mine)[:8], np.sort(every)[:8], atol=1e-12)
