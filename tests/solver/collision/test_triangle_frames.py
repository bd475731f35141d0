"""The mesh's segment-triangle kernel (solver.collision.triangle_frames) against the independent point-triangle
distance of tests/collision_check.py minimised along the segment, for random and for awkward segments (zero length,
in the face's plane, parallel to an edge, piercing the face, touching a corner)."""

from __future__ import annotations

import numpy as np
import pytest
from collision_check import along, minimise_convex, point_triangle
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from solver.collision.closest import segment_triangle
from solver.collision.triangle_frames import TriangleFrames

coordinate = st.floats(-2.0, 2.0, allow_nan=False, allow_infinity=False)
point = st.tuples(coordinate, coordinate, coordinate).map(np.array)


def awkward_segment(kind: str, a, b, c, p0, p1):
    """A segment of ``kind`` for the triangle a, b, c (p0, p1: random points to start from)."""
    normal = np.cross(b - a, c - a)
    if kind == "point":
        return p0, p0.copy()
    if kind == "in plane":
        return a + 0.3 * (b - a) + 0.2 * (c - a), a + 1.4 * (c - a) - 0.5 * (b - a)
    if kind == "parallel to an edge":
        lift = 0.1 * normal / np.linalg.norm(normal)
        return a + lift - 0.5 * (b - a), a + lift + 0.7 * (b - a)
    if kind == "piercing":
        inside = (a + b + c) / 3.0
        return inside - normal, inside + 0.5 * normal
    if kind == "touching a corner":
        return a, a + (p1 - p0)
    return p0, p1


def triangle_ok(a, b, c) -> bool:
    """Not degenerate, as a Mesh requires of its faces."""
    n = np.linalg.norm(np.cross(b - a, c - a))
    longest = max(np.linalg.norm(b - a), np.linalg.norm(c - b), np.linalg.norm(a - c))
    return bool(n > 1e-3 * longest**2 and longest > 1e-3)


KINDS = ["random", "point", "in plane", "parallel to an edge", "piercing", "touching a corner"]


@pytest.mark.slow  # 300 examples, each against a numerical minimisation: ~5 s
@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(a=point, b=point, c=point, p0=point, p1=point, kind=st.sampled_from(KINDS))
def test_closest_points_match_the_independent_reference(a, b, c, p0, p1, kind):
    if not triangle_ok(a, b, c):
        return
    s0, s1 = awkward_segment(kind, a, b, c, p0, p1)
    frames = TriangleFrames(a[None], b[None], c[None])
    t, x, y = frames.closest(s0[None], s1[None], np.array([0]))
    distance = float(np.linalg.norm(x - y))
    reference = float(minimise_convex(lambda s: point_triangle(along(s0[None], s1[None])(s), a, b, c), (1,))[0])
    assert abs(distance - reference) <= 1e-9 * max(1.0, reference)
    assert 0.0 <= t[0] <= 1.0 and np.allclose(x[0], s0 + t[0] * (s1 - s0), atol=1e-12)
    assert point_triangle(y[0], a, b, c) <= 1e-9  # the triangle's witness lies on it
    if kind == "piercing":
        assert distance <= 1e-9


def test_many_pairs_at_once_agree_with_the_general_kernel():
    rng = np.random.default_rng(7)
    a, b, c = (rng.normal(size=(40, 3)) for _ in range(3))
    frames = TriangleFrames(a, b, c)
    p0, p1 = rng.normal(size=(200, 3)), rng.normal(size=(200, 3))
    tri = rng.integers(0, 40, 200)
    _, x, y = frames.closest(p0, p1, tri)
    _, xr, yr = segment_triangle(p0, p1, a[tri], b[tri], c[tri])
    assert np.allclose(np.linalg.norm(x - y, axis=1), np.linalg.norm(xr - yr, axis=1), atol=1e-12)
