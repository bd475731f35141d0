"""Capsule distances (solver.collision) against independent brute-force references, their gradients against finite
differences, and no NaN for any finite input (degenerate segments, touching edges and corners, penetration)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from scipy.optimize import minimize, minimize_scalar

from solver.collision import (
    Box,
    Capsule,
    HalfSpace,
    Mesh,
    MeshIndex,
    Sphere,
    capsule_pairs,
    obstacle_distance,
)
from solver.collision.closest import point_triangle, segment_segment, segment_triangle
from solver.collision.generate import box_mesh, height_field


def fibonacci_directions(n: int) -> np.ndarray:
    i = np.arange(n) + 0.5
    polar, azimuth = np.arccos(1 - 2 * i / n), np.pi * (1 + 5**0.5) * i
    return np.stack([np.cos(azimuth) * np.sin(polar), np.sin(azimuth) * np.sin(polar), np.cos(polar)], axis=1)


DIRECTIONS = fibonacci_directions(6000)


def support_distance(p0, p1, support) -> float:
    """Signed distance of the segment p0-p1 and a convex set with support function h(n): the largest gap
    min(n.p0, n.p1) - h(n) over unit directions n (the distance when apart, minus the penetration depth when they
    overlap), by a dense direction search refined with Nelder-Mead."""

    def gap(n):
        n = n / np.linalg.norm(n, axis=-1, keepdims=True)
        return np.minimum(n @ p0, n @ p1) - support(n)

    values = gap(DIRECTIONS)
    best = values.max()
    for start in DIRECTIONS[np.argsort(values)[-3:]]:
        angles = [np.arccos(np.clip(start[2], -1, 1)), np.arctan2(start[1], start[0])]

        def f(x):
            n = np.array([[np.sin(x[0]) * np.cos(x[1]), np.sin(x[0]) * np.sin(x[1]), np.cos(x[0])]])
            return -gap(n)[0]

        res = minimize(f, angles, method="Nelder-Mead", options={"xatol": 1e-11, "fatol": 1e-13, "maxiter": 3000})
        best = max(best, -res.fun)
    return float(best)


def sampled_distance(p0, p1, point_distance) -> tuple[float, float]:
    """min over the segment of a point's signed distance: dense samples, then a bounded 1-D refinement.
    Returns (distance, t)."""
    ts = np.linspace(0.0, 1.0, 2001)
    values = point_distance(p0 + ts[:, None] * (p1 - p0))
    i = int(np.argmin(values))
    lo, hi = ts[max(i - 1, 0)], ts[min(i + 1, len(ts) - 1)]
    res = minimize_scalar(
        lambda t: point_distance((p0 + t * (p1 - p0))[None])[0],
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": 1e-12},
    )
    return (float(res.fun), float(res.x)) if res.fun < values[i] else (float(values[i]), float(ts[i]))


def random_rotation(rng) -> np.ndarray:
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


def random_segment(rng, scale=0.6) -> tuple[np.ndarray, np.ndarray]:
    """A random segment, every few draws degenerate: zero length, or parallel to a coordinate axis."""
    p0 = rng.normal(size=3) * scale
    kind = rng.integers(4)
    if kind == 0:
        return p0, p0.copy()
    if kind == 1:
        return p0, p0 + np.eye(3)[rng.integers(3)] * rng.uniform(-1, 1)
    return p0, p0 + rng.normal(size=3) * rng.choice([0.05, 0.4, 1.0])


def shapes(rng) -> list:
    rot = random_rotation(rng)
    return [
        Sphere(rng.normal(size=3) * 0.2, rng.uniform(0.1, 0.5)),
        Capsule(rng.normal(size=3) * 0.2, rng.normal(size=3) * 0.3, rng.uniform(0.05, 0.3)),
        Box(rng.normal(size=3) * 0.2, rng.uniform(0.05, 1.2, 3), rot),
    ]


def support_of(shape):
    if isinstance(shape, Sphere):
        return lambda n: n @ shape.center + shape.radius
    if isinstance(shape, Capsule):
        return lambda n: np.maximum(n @ shape.a, n @ shape.b) + shape.radius
    return lambda n: n @ shape.center + np.abs(n @ shape.rotation) @ shape.half


def test_convex_distances_match_the_support_function_reference():
    rng = np.random.default_rng(20)
    checked = {"apart": 0, "overlap": 0}
    for k in range(12):
        for shape in shapes(rng):
            p0, p1 = random_segment(rng, scale=0.2 if k % 2 else 0.8)
            radius = rng.uniform(0.0, 0.1)
            got = obstacle_distance(p0[None], p1[None], radius, shape)
            want = support_distance(p0, p1, support_of(shape)) - radius
            assert got.distance[0] == pytest.approx(want, abs=1e-8), (shape, p0, p1)
            checked["apart" if want + radius > 0 else "overlap"] += 1
    assert min(checked.values()) >= 5, checked


def test_apart_distances_match_dense_sampling_and_the_witness_is_the_closest_axis_point():
    rng = np.random.default_rng(21)
    for _ in range(15):
        sphere, capsule, box = shapes(rng)
        point_distances = {
            id(sphere): lambda x, s=sphere: np.linalg.norm(x - s.center, axis=1) - s.radius,
            id(capsule): lambda x, c=capsule: (
                np.array(
                    [
                        np.linalg.norm(
                            xi
                            - c.a
                            - np.clip((xi - c.a) @ (c.b - c.a) / ((c.b - c.a) @ (c.b - c.a)), 0, 1) * (c.b - c.a)
                        )
                        for xi in x
                    ]
                )
                - c.radius
            ),  # fmt: skip
            id(box): lambda x, b=box: np.linalg.norm(
                (x - b.center) @ b.rotation - np.clip((x - b.center) @ b.rotation, -b.half, b.half), axis=1
            ),
        }
        for shape in (sphere, capsule, box):
            p0, p1 = random_segment(rng, scale=1.5)
            want, t_want = sampled_distance(p0, p1, point_distances[id(shape)])
            if want <= 1e-3:
                continue  # overlapping: covered by the support-function test
            got = obstacle_distance(p0[None], p1[None], 0.0, shape)
            assert got.distance[0] == pytest.approx(want, abs=1e-9)
            assert np.allclose(got.point[0], p0 + got.t[0] * (p1 - p0))
            assert np.linalg.norm(got.point[0] - (p0 + t_want * (p1 - p0))) < 1e-4 or np.allclose(p0, p1)


def test_halfspace_takes_the_lower_end_and_the_surface_point_lies_on_the_plane():
    rng = np.random.default_rng(22)
    for _ in range(30):
        plane = HalfSpace(rng.normal(size=3), rng.normal(size=3))
        p0, p1 = random_segment(rng, scale=2.0)
        got = obstacle_distance(p0[None], p1[None], 0.05, plane)
        want = min((p0 - plane.point) @ plane.normal, (p1 - plane.point) @ plane.normal) - 0.05
        assert got.distance[0] == pytest.approx(want, abs=1e-12)
        assert np.allclose(got.normal[0], plane.normal)
        assert (got.closest[0] - plane.point) @ plane.normal == pytest.approx(0.0, abs=1e-12)


def test_a_point_inside_a_box_has_minus_the_distance_to_the_nearest_face():
    box = Box([1.0, 2.0, 3.0], [0.4, 1.0, 2.0])
    p = np.array([[1.15, 2.1, 3.3]])  # 5 cm from the +x face, farther from the others
    got = obstacle_distance(p, p, 0.01, box)
    assert got.distance[0] == pytest.approx(-0.05 - 0.01)
    assert np.allclose(got.normal[0], [1.0, 0.0, 0.0])
    assert np.allclose(got.closest[0], [1.2, 2.1, 3.3])


def test_a_segment_through_a_box_is_pushed_out_sideways_by_the_shortest_translation():
    box = Box([0.0, 0.0, 0.0], [2.0, 0.6, 1.0])  # long in x, thinnest in y
    got = obstacle_distance(np.array([[-3.0, 0.1, 0.0]]), np.array([[3.0, 0.1, 0.0]]), 0.0, box)
    assert got.distance[0] == pytest.approx(-0.2)  # 0.2 m to y = +0.3; the deepest point alone would say -0.3
    assert np.allclose(got.normal[0], [0.0, 1.0, 0.0])


def test_touching_an_edge_or_a_corner_gives_zero_and_a_unit_normal():
    box = Box([0.0, 0.0, 0.0], [1.0, 1.0, 1.0])
    edge = obstacle_distance(np.array([[-1.0, 0.5, 0.5]]), np.array([[1.0, 0.5, 0.5]]), 0.0, box)
    corner = obstacle_distance(np.array([[0.5, 0.5, 0.5]]), np.array([[1.0, 1.0, 1.0]]), 0.0, box)
    for got in (edge, corner):
        assert got.distance[0] == pytest.approx(0.0, abs=1e-15)
        assert np.linalg.norm(got.normal[0]) == pytest.approx(1.0)


def test_parallel_and_zero_length_segments_match_a_dense_reference():
    rng = np.random.default_rng(23)
    ts = np.linspace(0, 1, 801)
    for k in range(60):
        p0, q0 = rng.normal(size=3), rng.normal(size=3)
        d = rng.normal(size=3)
        p1 = p0 + d * rng.uniform(-1, 1) * (k % 3 != 0)
        q1 = q0 + d * rng.uniform(-2, 2) * (k % 5 != 0)
        s, t = segment_segment(p0, p1, q0, q1)
        got = np.linalg.norm(p0 + s * (p1 - p0) - q0 - t * (q1 - q0))
        a, b = p0 + ts[:, None] * (p1 - p0), q0 + ts[:, None] * (q1 - q0)
        want = np.min(np.linalg.norm(a[:, None] - b[None], axis=2))
        assert want - 2e-3 <= got <= want + 1e-12


def closed_box_index(center=(0.0, 0.0, 0.0), size=(0.8, 0.6, 0.5), divisions=3, rotation=None) -> MeshIndex:
    return MeshIndex(Mesh(*box_mesh(center, size, divisions, rotation)))


def terrain_index() -> MeshIndex:
    vertices, faces = height_field([-0.6, -0.6, 0.0], [1.2, 1.2], (7, 6), lambda x, y: 0.1 * np.sin(3 * x) * y)
    return MeshIndex(Mesh(vertices, faces))


def finite_difference_check(distance, p0, p1, step=1e-6) -> tuple[float, int]:
    """Largest |central difference - analytic| over the 6 end-point coordinates, and how many were skipped because
    the one-sided differences disagree (a kink: the closest pair is not unique there)."""
    got = distance(p0, p1)
    t, n = got.t[0], got.normal[0]
    worst, skipped = 0.0, 0
    for end, weight in ((0, 1 - t), (1, t)):
        for axis in range(3):
            e = np.zeros(3)
            e[axis] = step
            ends = [p0, p1]
            values = []
            for sign in (1, 0, -1):
                moved = list(ends)
                moved[end] = ends[end] + sign * e
                values.append(distance(*moved).distance[0])
            ahead, behind = (values[0] - values[1]) / step, (values[1] - values[2]) / step
            if abs(ahead - behind) > 1e-4:
                skipped += 1
                continue
            worst = max(worst, abs((values[0] - values[2]) / (2 * step) - weight * n[axis]))
    return worst, skipped


RADIUS = 0.05


@pytest.mark.parametrize("kind", ["sphere", "capsule", "box", "halfspace", "closed mesh", "open mesh"])
def test_distance_gradient_is_the_normal_split_by_the_witness_parameter(kind):
    rng = np.random.default_rng(24)
    obstacles = {
        "sphere": Sphere([0.1, 0.2, 0.0], 0.4),
        "capsule": Capsule([0.0, 0.0, 0.0], [0.5, 0.2, 0.1], 0.2),
        "box": Box([0.1, 0.0, 0.0], [0.8, 0.6, 0.5], random_rotation(rng)),
        "halfspace": HalfSpace([0.0, 0.0, 0.1], [0.1, 0.2, 1.0]),
        "closed mesh": closed_box_index(rotation=random_rotation(rng)),
        "open mesh": terrain_index(),
    }
    obstacle = obstacles[kind]
    checked, penetrating = 0, 0
    for _ in range(40):
        p0 = rng.normal(size=3) * 0.5
        p1 = p0 + rng.normal(size=3) * 0.4
        distance = lambda a, b: obstacle_distance(a[None], b[None], RADIUS, obstacle, margin=10.0)  # noqa: E731
        if kind == "open mesh" and distance(p0, p1).distance[0] <= -RADIUS + 1e-9:
            continue  # an axis through an open sheet: distance -radius, flat, not the normal (documented)
        worst, skipped = finite_difference_check(distance, p0, p1)
        assert worst < 1e-6, (kind, p0, p1, worst)
        checked += 6 - skipped
        penetrating += distance(p0, p1).distance[0] < 0
    assert checked >= 6 * 25, checked
    if kind not in ("halfspace", "open mesh"):
        assert penetrating >= 3, penetrating


def test_capsule_pairs_match_the_single_capsule_query_and_are_antisymmetric():
    rng = np.random.default_rng(25)
    p0, p1, radii = rng.normal(size=(8, 3)), rng.normal(size=(8, 3)), rng.uniform(0.02, 0.2, 8)
    p1[2] = p0[2]  # a zero-length capsule
    p1[3] = p0[3] + (p1[4] - p0[4])  # parallel to capsule 4
    i, j = np.triu_indices(8, 1)
    pairs = capsule_pairs(p0, p1, radii, i, j)
    swapped = capsule_pairs(p0, p1, radii, j, i)
    assert np.allclose(pairs.distance, swapped.distance)
    assert np.allclose(pairs.normal, -swapped.normal)
    for m in range(len(i)):
        single = obstacle_distance(
            p0[i[m]][None], p1[i[m]][None], radii[i[m]], Capsule(p0[j[m]], p1[j[m]], radii[j[m]])
        )
        assert pairs.distance[m] == pytest.approx(single.distance[0], abs=1e-12)
        gap = pairs.point[m] - pairs.point_other[m]
        assert np.linalg.norm(gap) == pytest.approx(pairs.distance[m] + radii[i[m]] + radii[j[m]], abs=1e-12)
        assert np.allclose(pairs.point[m], p0[i[m]] + pairs.t[m] * (p1[i[m]] - p0[i[m]]))
        assert np.allclose(pairs.point_other[m], p0[j[m]] + pairs.t_other[m] * (p1[j[m]] - p0[j[m]]))


def test_capsule_pair_gradient_moves_both_capsules():
    rng = np.random.default_rng(26)
    for _ in range(20):
        p0, p1 = rng.normal(size=(2, 3)), rng.normal(size=(2, 3))
        got = capsule_pairs(p0, p1, 0.05, [0], [1])
        n = got.normal[0]
        for body, weight in ((0, (1 - got.t[0], got.t[0])), (1, (-(1 - got.t_other[0]), -got.t_other[0]))):
            for end, w in zip((p0, p1), weight, strict=True):
                for axis in range(3):
                    moved = [p0.copy(), p1.copy()]
                    which = 0 if end is p0 else 1
                    moved[which][body, axis] += 1e-6
                    ahead = capsule_pairs(*moved, 0.05, [0], [1]).distance[0]
                    moved[which][body, axis] -= 2e-6
                    behind = capsule_pairs(*moved, 0.05, [0], [1]).distance[0]
                    assert (ahead - behind) / 2e-6 == pytest.approx(w * n[axis], abs=1e-6)


def test_mesh_distance_is_exact_against_every_triangle_and_inf_beyond_the_margin():
    rng = np.random.default_rng(27)
    for index in (terrain_index(), closed_box_index(divisions=4, rotation=random_rotation(rng))):
        p0 = rng.normal(size=(300, 3)) * 0.6
        p1 = p0 + rng.normal(size=(300, 3)) * 0.3
        p1[::7] = p0[::7]
        radii = rng.uniform(0.0, 0.1, 300)
        got = obstacle_distance(p0, p1, radii, index, margin=0.15)
        _, x, y = segment_triangle(p0[:, None], p1[:, None], index.a[None], index.b[None], index.c[None])
        unsigned = np.min(np.linalg.norm(x - y, axis=-1), axis=1) - radii
        apart = unsigned > 1e-9
        if index.closed:
            apart &= ~index.contains(p0)
        near = apart & (unsigned <= 0.15)
        assert near.sum() > 20 and (apart & (unsigned > 0.15)).sum() > 20
        assert np.allclose(got.distance[near], unsigned[near], atol=1e-12)
        assert np.isinf(got.distance[apart & (unsigned > 0.15)]).all()
        assert np.all(got.distance[~apart] < 0)


def test_a_closed_box_mesh_agrees_with_the_box_outside_and_measures_depth_inside():
    rng = np.random.default_rng(28)
    rot = random_rotation(rng)
    box = Box([0.1, -0.2, 0.3], [0.9, 0.5, 0.7], rot)
    index = closed_box_index(box.center, box.size, 5, rot)
    p0 = box.center + rng.normal(size=(400, 3)) * 0.5
    p1 = p0 + rng.normal(size=(400, 3)) * 0.25
    got = obstacle_distance(p0, p1, 0.03, index, margin=0.2)
    want = obstacle_distance(p0, p1, 0.03, box)
    apart = want.distance > -0.03  # the axis outside the box
    near = apart & (want.distance <= 0.2)
    assert np.allclose(got.distance[near], want.distance[near], atol=1e-12)
    assert np.allclose(got.normal[near], want.normal[near], atol=1e-9)
    assert np.all(got.distance[~apart] <= -0.03)
    # inside: minus the depth of the deepest of 9 axis samples (distance to the nearest face)
    ts = np.linspace(0, 1, 9)
    for k in np.flatnonzero(~apart)[:60]:
        local = (p0[k] + ts[:, None] * (p1[k] - p0[k]) - box.center) @ rot
        depth = np.min(box.half - np.abs(local), axis=1)
        assert got.distance[k] == pytest.approx(min(-depth.max(), 0.0) - 0.03, abs=1e-9)


def test_nearest_surface_point_of_points_matches_every_triangle():
    rng = np.random.default_rng(29)
    index = closed_box_index(divisions=6)
    points = rng.normal(size=(200, 3)) * 0.5
    dist, near, _ = index.nearest(points)
    closest = point_triangle(points[:, None], index.a[None], index.b[None], index.c[None])
    want = np.min(np.linalg.norm(closest - points[:, None], axis=-1), axis=1)
    assert np.allclose(dist, want, atol=1e-12)
    assert np.allclose(np.linalg.norm(near - points, axis=1), dist)


coordinate = st.sampled_from([-1.0, -0.5, -0.25, 0.0, 0.25, 0.5, 1.0]) | st.floats(-2, 2, allow_nan=False)
vector = st.tuples(coordinate, coordinate, coordinate).map(np.array)
OBSTACLES = [
    Sphere([0.0, 0.0, 0.0], 0.5),
    Capsule([-0.5, 0.0, 0.0], [0.5, 0.0, 0.0], 0.25),
    Box([0.0, 0.0, 0.0], [1.0, 1.0, 0.5]),
    HalfSpace([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
    closed_box_index(size=(1.0, 1.0, 0.5), divisions=2),
    terrain_index(),
]


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(p0=vector, p1=vector, same=st.booleans(), radius=st.sampled_from([0.0, 0.05]))
@example(p0=np.array([-1.0, -1.0, 7.8e-162]), p1=np.array([-1.0, -1.0, -1.0]), same=False, radius=0.0)  # subnormal
@example(p0=np.array([-1.0, -1.0, -1.0]), p1=np.array([-0.5, 0.0, 7.8e-162]), same=False, radius=0.05)
def test_no_nan_for_any_finite_input(p0, p1, same, radius):
    if same:
        p1 = p0
    p0s, p1s = np.stack([p0, p1, p0]), np.stack([p1, p0, p0])
    for obstacle in OBSTACLES:
        got = obstacle_distance(p0s, p1s, radius, obstacle, margin=0.3)
        finite = np.isfinite(got.distance)
        assert not np.isnan(got.distance).any()
        assert np.isfinite(got.point).all() and np.isfinite(got.normal).all() and np.isfinite(got.closest).all()
        assert np.allclose(np.linalg.norm(got.normal[finite], axis=1), 1.0)
        assert np.all((got.t >= 0) & (got.t <= 1))
        assert np.allclose(got.point, p0s + got.t[:, None] * (p1s - p0s))
        gap = got.point - got.closest
        along = np.einsum("ij,ij->i", gap, got.normal)
        assert np.allclose(along[finite], got.distance[finite] + radius, atol=1e-9)
    pairs = capsule_pairs(p0s, p1s, radius, [0, 1, 2], [1, 2, 0])
    assert np.isfinite(pairs.distance).all() and np.allclose(np.linalg.norm(pairs.normal, axis=1), 1.0)


def test_a_segment_piercing_a_triangle_meets_it_at_the_crossing():
    a, b, c = np.array([0.0, 0.0, 0.0]), np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    t, x, y = segment_triangle(np.array([0.2, 0.3, -0.25]), np.array([0.2, 0.3, 0.75]), a, b, c)
    assert t == pytest.approx(0.25) and np.allclose(x, [0.2, 0.3, 0.0]) and np.allclose(y, x)
    t, x, y = segment_triangle(np.array([0.2, 0.3, 0.5]), np.array([0.6, 0.7, 0.5]), a, b, c)  # parallel, over
    assert np.linalg.norm(x - y) == pytest.approx(0.5) and y[2] == 0.0


def test_an_axis_through_an_open_sheet_is_pushed_to_the_side_with_more_of_it():
    sheet = MeshIndex(Mesh(*height_field([-1.0, -1.0, 0.0], [2.0, 2.0], (4, 4), lambda x, y: 0 * x)))
    mostly_above = obstacle_distance(np.array([[0.1, 0.1, -0.1]]), np.array([[0.1, 0.1, 0.3]]), 0.05, sheet, 0.1)
    mostly_below = obstacle_distance(np.array([[0.1, 0.1, 0.1]]), np.array([[0.1, 0.1, -0.3]]), 0.05, sheet, 0.1)
    assert mostly_above.distance[0] == pytest.approx(-0.05) and np.allclose(mostly_above.normal[0], [0, 0, 1])
    assert mostly_below.distance[0] == pytest.approx(-0.05) and np.allclose(mostly_below.normal[0], [0, 0, -1])


def test_a_box_query_with_a_margin_leaves_out_only_far_capsules():
    """With a margin, a box's query is exact for every capsule within it and +inf only beyond it (the capsules
    far from its bounding box are not computed)."""
    rng = np.random.default_rng(7)
    box = Box(np.array([0.2, -0.1, 0.5]), np.array([0.6, 0.3, 0.2]), _rotation_about_z(0.6))
    p0, p1 = rng.uniform(-0.6, 0.9, (400, 3)) + [0, 0, 0.3], rng.uniform(-1.0, 1.0, (400, 3))
    p1 = p0 + 0.3 * (p1 - p0) / np.linalg.norm(p1 - p0, axis=1)[:, None]
    radii = rng.uniform(0.02, 0.1, 400)
    exact = obstacle_distance(p0, p1, radii, box)
    near = obstacle_distance(p0, p1, radii, box, margin=0.05)
    within = exact.distance <= 0.05
    assert within.sum() > 20 and (~within).sum() > 20
    for mine, theirs in zip(near, exact, strict=True):
        # equal up to a few ulp: the kept capsules go through the BLAS/SIMD kernels as a smaller batch, which some
        # CPUs' kernels round differently from the whole one (1e-17 m seen)
        np.testing.assert_allclose(mine[within], theirs[within], rtol=0, atol=1e-12)
    assert (near.distance[~within] > 0.05).all()  # +inf where left out, else the exact distance
    assert np.isinf(near.distance).sum() > 20


def _rotation_about_z(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_a_mesh_query_from_memory_answers_as_a_fresh_one():
    """Capsules that move a little (or a lot) between queries get the same answer through a NearMemory as without
    it: the remembered triangles always hold the nearest one."""
    from solver.collision.mesh_index import NearMemory

    rng = np.random.default_rng(11)
    for index in (terrain_index(), closed_box_index(divisions=8, rotation=random_rotation(rng))):
        p0 = rng.normal(size=(60, 3)) * 0.5
        p1 = p0 + rng.normal(size=(60, 3)) * 0.2
        radii = rng.uniform(0.0, 0.08, 60)
        memory = NearMemory(60)
        reused = 0
        for step in range(40):
            scale = 0.05 if step % 5 == 4 else 0.004  # mostly within the memory's reach, now and then beyond it
            p0, p1 = p0 + rng.normal(size=p0.shape) * scale, p1 + rng.normal(size=p1.shape) * scale
            margin = 0.1 if step % 13 else 0.2  # a wider margin than remembered: searched again
            asked = memory.ends.copy()
            got = obstacle_distance(p0, p1, radii, index, margin, memory)
            reused += int(np.sum(np.all(memory.ends == asked, axis=1) & np.isfinite(asked[:, 0])))
            want = obstacle_distance(p0, p1, radii, index, margin)
            for mine, theirs in zip(got, want, strict=True):
                np.testing.assert_allclose(mine, theirs, rtol=0, atol=1e-12)
        assert reused > 200  # the memory was used, not searched around every time
