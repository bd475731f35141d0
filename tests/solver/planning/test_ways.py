"""Ways for the hand and a carried box (issue 36, "Paths"): around a bench from a floor pallet to a shelf behind it,
straight when nothing is in the way, one line naming what blocks a way, the same way for the same seed, and
arc-length resampling."""

from __future__ import annotations

import numpy as np
import pytest

from solver.collision import Box, HalfSpace
from solver.planning import HAND_RADIUS, MARGIN, CarriedBox, arc_lengths, at_shares, find_way

FLOOR = HalfSpace([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], name="floor")
PALLET = Box([0.0, -0.6, 0.075], [0.8, 0.6, 0.15], name="pallet")
BENCH = Box([0.0, 0.2, 0.45], [1.2, 0.5, 0.9], name="bench")
SHELF = Box([0.0, 1.0, 1.0], [1.0, 0.4, 0.04], name="shelf")
STATION = [FLOOR, PALLET, BENCH, SHELF]
TOTE = CarriedBox(np.array([0.4, 0.3, 0.3]), name="tote")
ON_PALLET = np.array([0.0, -0.6, 0.15 + 0.15])  # the tote's centre standing on the pallet
ON_SHELF = np.array([0.0, 1.0, 1.02 + 0.15])  # ... standing on the shelf


def along(points: np.ndarray, step: float = 0.005) -> np.ndarray:
    """Points every ``step`` m along the polyline."""
    total = arc_lengths(points)[-1]
    return at_shares(points, np.linspace(0.0, 1.0, max(2, int(np.ceil(total / step)) + 1)))


def surface_grid(half: np.ndarray, n: int = 7) -> np.ndarray:
    """Points on the surface of the box |x_i| <= half_i (its own axes), n per edge."""
    g = np.linspace(-1.0, 1.0, n)
    cube = np.array([[x, y, z] for x in g for y in g for z in g])
    return cube[np.abs(cube).max(axis=1) == 1.0] * half


def inside_box(points: np.ndarray, box: Box, grow: float) -> np.ndarray:
    """Which world ``points`` are inside ``box`` grown by ``grow`` m (an independent test: no distance code)."""
    local = (points - box.center) @ box.rotation
    return np.all(np.abs(local) < box.half + grow, axis=1)


def distance_to_box(points: np.ndarray, box: Box) -> np.ndarray:
    """Distance (m) of world ``points`` outside ``box`` to it (0 inside), from the box's own axes."""
    local = (points - box.center) @ box.rotation
    return np.linalg.norm(np.maximum(np.abs(local) - box.half, 0.0), axis=1)


def test_a_tote_goes_over_the_bench_from_the_pallet_to_the_shelf_behind_it():
    """The straight way runs through the bench; the way found leaves the pallet, passes over the bench and sets the
    tote on the shelf; no point of the tote's surface, sampled every 5 mm along the way, comes inside the bench or the
    shelf (grown by most of the margin), nor below the floor; it takes well under a second's worth of samples."""
    way = find_way(ON_PALLET, ON_SHELF, TOTE, STATION, seed=1)
    assert way.found, way.blocked
    assert np.allclose(way.points[0], ON_PALLET) and np.allclose(way.points[-1], ON_SHELF)
    assert len(way.points) > 2 and way.samples > 0
    grid = surface_grid(TOTE.half)
    middle = along(way.points[1:-1])  # the pieces leaving the pallet and reaching the shelf touch them at one end
    for centre in middle:
        tote = centre + grid
        for obstacle in (BENCH, SHELF, PALLET):
            assert not inside_box(tote, obstacle, 0.5 * MARGIN).any(), (obstacle.name, centre)
        assert tote[:, 2].min() > 0.0
    over = middle[np.abs(middle[:, 1] - BENCH.center[1]) < BENCH.half[1]]
    assert (over[:, 2] - TOTE.half[2] > BENCH.center[2] + BENCH.half[2]).all()  # over the bench's top, not round it
    assert any("leaves its start" in note and "pallet" in note for note in way.notes)


def test_straight_when_nothing_is_in_the_way():
    """A reach in the open: the way is the start and the goal, nothing searched."""
    start, goal = np.array([0.5, -0.6, 1.0]), np.array([0.5, -0.2, 1.3])
    for carried in (None, TOTE):
        way = find_way(start, goal, carried, STATION)
        assert way.found and way.samples == 0
        assert np.allclose(way.points, [start, goal])


def test_a_hand_goes_round_a_wall():
    """A wall between the hand's start and goal: the way keeps the hand ball the margin from it all along."""
    wall = Box([0.0, 0.0, 1.0], [0.6, 0.05, 0.6], name="wall")
    way = find_way([0.0, -0.4, 1.0], [0.0, 0.4, 1.0], None, [FLOOR, wall], seed=3)
    assert way.found, way.blocked
    assert distance_to_box(along(way.points), wall).min() > HAND_RADIUS + 0.9 * MARGIN


def test_a_goal_inside_an_obstacle_is_blocked_by_it_in_one_line():
    way = find_way(ON_PALLET, [0.0, 0.2, 0.5], None, STATION)
    assert not way.found and len(way.points) == 0
    assert way.blocked.startswith("blocked by bench: the hand's goal (0.00, 0.20, 0.50) m is inside it")
    assert "\n" not in way.blocked


def test_an_enclosed_goal_names_what_shuts_it_in():
    """The goal in a closed cabinet (six walls): no way, and the line names the cabinet's walls."""
    walls = [Box([0.0, 1.0, 1.0 + dz], [0.6, 0.6, 0.02], name="cabinet top" if dz > 0 else "cabinet bottom")
             for dz in (-0.3, 0.3)]  # fmt: skip
    walls += [Box([dx, 1.0, 1.0], [0.02, 0.6, 0.6], name="cabinet side") for dx in (-0.3, 0.3)]
    walls += [Box([0.0, 1.0 + dy, 1.0], [0.6, 0.02, 0.6], name="cabinet door") for dy in (-0.3, 0.3)]
    way = find_way([0.0, -0.3, 1.0], [0.0, 1.0, 1.0], None, [FLOOR, *walls], samples=200)
    assert not way.found
    assert way.blocked.startswith("blocked by cabinet")
    assert "goal (0.00, 1.00, 1.00) m is shut in" in way.blocked and "\n" not in way.blocked


def test_the_same_seed_gives_the_same_way():
    a = find_way(ON_PALLET, ON_SHELF, TOTE, STATION, seed=7)
    b = find_way(ON_PALLET, ON_SHELF, TOTE, STATION, seed=7)
    assert a.found and b.found
    assert a.points.shape == b.points.shape and np.allclose(a.points, b.points, rtol=0, atol=1e-12)


def test_a_turning_tote_ends_in_the_goal_orientation():
    """The tote turns a quarter about z from the pallet to the shelf: the orientations along the way start and end
    as asked."""
    quarter = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    turning = CarriedBox(TOTE.size, np.eye(3), quarter, name="tote")
    way = find_way(ON_PALLET, ON_SHELF, turning, STATION, seed=1)
    assert way.found, way.blocked
    assert np.allclose(way.rotations[0], np.eye(3), atol=1e-9) and np.allclose(way.rotations[-1], quarter, atol=1e-9)


@pytest.mark.parametrize("shares", [[0.0, 1.0], [0.25, 0.5, 0.75]])
def test_resampling_by_arc_length(shares):
    """An L of legs 0.3 m and 0.1 m: a share of the length lands that far along it."""
    l_shape = np.array([[0.0, 0.0, 0.0], [0.3, 0.0, 0.0], [0.3, 0.1, 0.0]])
    got = at_shares(l_shape, shares)
    for s, p in zip(shares, got, strict=True):
        d = 0.4 * s
        want = [d, 0.0, 0.0] if d <= 0.3 else [0.3, d - 0.3, 0.0]
        assert np.allclose(p, want, atol=1e-12)
    assert np.allclose(at_shares(l_shape[:1], [0.0, 0.5]), [l_shape[0], l_shape[0]])
