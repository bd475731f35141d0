"""The swept check's certificate by the kernel equals the NumPy path's (SweptBody.any_uncertain): obstacles and the
body's own pairs, a support's foot not against the floor, bounds from far inside to far outside the distances."""

from __future__ import annotations

import numpy as np
import pytest

from solver import kernels
from solver.collision import Box
from solver.collision.body import capsules_of
from solver.collision.self_pairs import self_pairs
from solver.collision.sweep import SweptBody
from solver.constraints.clearance import FLOOR
from solver.io.scenario.bodies import load_body

pytest.importorskip("numba")


def test_any_uncertain():
    """Random distances and motions at scales that leave every pair certified, some or none; relative() on a self
    pair adds the partner's motion."""
    model = load_body(preset="male_50")
    caps = capsules_of(model)
    obstacles = [FLOOR, Box(np.array([0.0, -0.5, 0.8]), np.array([0.6, 0.3, 0.05]), name="table")]
    pairs = np.ones((len(caps), len(obstacles)), dtype=bool)
    pairs[caps.names.index("foot_r"), 0] = False
    body = SweptBody(model, obstacles, pairs, own=self_pairs(model, caps))
    own = np.flatnonzero(body.partner[:, len(obstacles)] >= 0)[0]
    motion = np.arange(len(caps), dtype=float)
    assert body.relative(motion)[own, len(obstacles)] == own + body.partner[own, len(obstacles)]
    rng = np.random.default_rng(8)
    seen = set()
    for scale in (1e-4, 1e-3, 1e-2, 0.05, 0.2, 1.0):
        for _ in range(20):
            d_p = rng.uniform(-0.01, 0.3, body.pairs.shape)
            first, second, way = (rng.uniform(0.0, scale, len(caps)) for _ in range(3))
            got = {}
            for compiled in (False, True):
                with kernels.using(compiled):
                    got[compiled] = body.any_uncertain(d_p, first, second, way)
            assert got[True] == got[False]
            seen.add(got[True])
    assert seen == {False, True}


def test_way_bounds():
    """SweptBody.bounds of ways from small to large joint steps, one of no move at all."""
    model = load_body(preset="male_50")
    caps = capsules_of(model)
    body = SweptBody(model, [FLOOR], np.ones((len(caps), 1), dtype=bool))
    rng = np.random.default_rng(4)
    start = body.pose(np.zeros(model.n))
    ways = [(start, start)]
    for scale in (1e-4, 1e-2, 0.3, 2.0):
        ways.append((start, body.pose(rng.uniform(-scale, scale, model.n))))
    got = {}
    for compiled in (False, True):
        with kernels.using(compiled):
            got[compiled] = body.bounds(ways)
    assert np.all(got[False][0] == 0.0) and np.all(got[False][-1] > 0.0)
    np.testing.assert_allclose(got[True], got[False], rtol=1e-12, atol=1e-15)
