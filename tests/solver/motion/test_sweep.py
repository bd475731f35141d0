"""Swept motion between frames (issue 20, "no part jumps through a thin obstacle between frames"): the path bound,
the swept check against brute-force sampling, a hand keyed through a 1 cm plate, and no sub-sampling when nothing
is near."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from bench.long_motion import long_motion
from solver import load_scenario
from solver.collision import Box, Mesh, Sphere, capsule_pairs, obstacle_distance
from solver.collision.body import capsules_of
from solver.collision.boxes import box_corners
from solver.collision.carried import carried_frame
from solver.collision.generate import box_mesh
from solver.collision.self_pairs import self_pairs
from solver.collision.sweep import TOLERANCE, SweptBody, path_weights_of
from solver.comfort import BEHAVIOUR
from solver.io.scenario.bodies import load_body
from solver.io.toml_write import dumps_toml
from solver.motion import between_frames
from solver.motion.between_frames import MotionSweep, planted_parts
from solver.motion.frames import solve_frames
from solver.problem.problem import Problem, ProblemSpec, Target

PLATE_MOTION = """
name = "hand through a plate"
[manikin]
preset = "male_50"
[motion]
start = 1
end = {end}
[[targets]]
tcp = "hand_r"
lock = ["x", "y", "z"]
[[targets.keys]]
frame = 2
position = [-0.35, -0.40, 1.0]
[[targets.keys]]
frame = 3
position = [-0.05, -0.40, 1.0]
[[targets]]
tcp = "foot_r"
position = [-0.083, 0.0, 0.0]
lock = ["x", "y", "z", "rx", "ry"]
support = true
[[targets]]
tcp = "foot_l"
position = [0.083, 0.0, 0.0]
lock = ["x", "y", "z", "rx", "ry"]
support = true
"""
# 1 cm thick, 8 cm square, across the way of the right hand from frame 2 to frame 3 (30 cm to the left)
PLATE = """
[[obstacles]]
name = "plate"
kind = "box"
center = [-0.216, -0.43, 0.99]
size = [0.01, 0.08, 0.08]
"""
PLATE_BOX = Box([-0.216, -0.43, 0.99], [0.01, 0.08, 0.08], name="plate")


@pytest.fixture(scope="module")
def male50():
    return load_body(preset="male_50")


def plate_motion(tmp_path: Path, plate: bool, end: int = 3):
    path = tmp_path / f"plate_{plate}_{end}.toml"
    path.write_text(PLATE_MOTION.format(end=end) + (PLATE if plate else ""), encoding="utf-8")
    return load_scenario(path)


def deepest_on_the_way(model, theta_a, theta_b, obstacles: list, samples: int = 400) -> np.ndarray:
    """Brute force: (k, m) the deepest penetration (m, > 0 inside) of each capsule into each obstacle at ``samples``
    evenly spaced poses of the linear joint interpolation."""
    caps = capsules_of(model)
    worst = np.full((len(caps), len(obstacles)), -np.inf)
    for s in np.linspace(0.0, 1.0, samples):
        p0, p1 = caps.world(model.forward((1 - s) * theta_a + s * theta_b))
        for o, ob in enumerate(obstacles):
            worst[:, o] = np.maximum(worst[:, o], -obstacle_distance(p0, p1, caps.radius, ob).distance)
    return worst


def deepest_part(model, theta_a, theta_b, obstacle, part: str, samples: int = 400) -> float:
    """:func:`deepest_on_the_way` of one capsule into one obstacle."""
    return float(
        deepest_on_the_way(model, theta_a, theta_b, [obstacle], samples)[capsules_of(model).names.index(part), 0]
    )


def random_pair(model, rng, scale: float) -> tuple[np.ndarray, np.ndarray]:
    """Two poses within the joint ranges, at most ``scale`` rad (a tenth of it in m for a slide) apart per joint."""
    lower, upper = np.maximum(model.lower, -2.0), np.minimum(model.upper, 2.0)
    a = rng.uniform(lower, upper) * 0.5
    step = rng.uniform(-1.0, 1.0, model.n) * np.where(model.prismatic, 0.1 * scale, scale)
    return a, np.clip(a + step, model.lower, model.upper)


def test_the_bounds_hold_for_every_capsule_point_on_the_way(male50):
    """The path bound L_k bounds the path length of both ends and the middle of every capsule's axis along the joint
    interpolation, and M_k (the smaller of L_k and chord + 1.5 W_k L_k) bounds their speed everywhere on it."""
    caps = capsules_of(male50)
    body = SweptBody(male50, [], np.zeros((len(caps), 0)))
    rng = np.random.default_rng(3)
    for scale in (0.005, 0.05, 0.35, 1.0):
        for _ in range(3):
            a, b = random_pair(male50, rng, scale)
            length, bound = path_weights_of(male50) @ np.abs(b - a), body.bound(body.pose(a), body.pose(b))
            points = []
            for s in np.linspace(0.0, 1.0, 401):
                p0, p1 = caps.world(male50.forward((1 - s) * a + s * b))
                points.append(np.stack([p0, p1, 0.5 * (p0 + p1)]))
            moves = np.linalg.norm(np.diff(np.array(points), axis=0), axis=-1)  # (400, 3, k)
            assert np.all(moves.sum(axis=0) <= length[None, :] + 1e-9), scale
            assert np.all(moves.max(axis=0) * 400 <= bound[None, :] * (1 + 1e-6) + 1e-12), scale
            assert np.all(bound <= length + 1e-12)
            if scale <= 0.005:  # small steps (a long motion's): the chord bound is the tighter one
                assert bound.sum() < 0.5 * length.sum(), bound.sum() / length.sum()


@pytest.mark.parametrize("seed", [0, *(pytest.param(s, marks=pytest.mark.slow) for s in range(1, 4))])  # ~1 s each
def test_swept_check_agrees_with_brute_force_sampling(male50, seed):
    """Random motions of the right arm past random obstacles (thin plates as boxes and closed meshes, spheres) placed
    on the hand's way: every pair that brute-force sampling finds deeper than 2 tol is reported, and every reported
    crossing is real (its own sample is deeper than tol)."""
    rng = np.random.default_rng(100 + seed)
    caps = capsules_of(male50)
    deep = 0
    for _ in range(3):
        a, b = random_pair(male50, rng, 0.35)
        mid = caps.world(male50.forward(0.5 * (a + b)))
        k = caps.names.index(rng.choice(["hand_r", "forearm_r", "hand_l"]))
        centre = 0.5 * (mid[0][k] + mid[1][k]) + rng.normal(0.0, 0.03, 3)
        axis = np.linalg.qr(rng.normal(size=(3, 3)))[0]
        rotation = axis * np.sign(np.linalg.det(axis))
        size = np.array([rng.uniform(0.005, 0.02), rng.uniform(0.05, 0.3), rng.uniform(0.05, 0.3)])
        obstacles = [
            Box(centre, size, rotation, name="plate"),
            Mesh(*box_mesh(centre + 0.05, size, 1, rotation), name="thin mesh"),
            Sphere(centre - 0.05, rng.uniform(0.01, 0.05), name="ball"),
        ]
        body = SweptBody(male50, obstacles, np.ones((len(caps), len(obstacles)), dtype=bool))
        pa, pb = body.pose(a), body.pose(b)
        margin = float(body.bound(pa, pb).max()) + 2 * TOLERANCE
        d_a, d_b = body.distances(pa, margin), body.distances(pb, margin)
        report = body.check(pa, pb, d_a, d_b, margin)
        found = {(c.part, c.obstacle) for c in report.crossings}
        for c in report.crossings:  # real: the distance at the reported fraction is that deep
            j, o = caps.names.index(c.part), [ob.name for ob in obstacles].index(c.obstacle)
            p0, p1 = caps.world(male50.forward((1 - c.s) * a + c.s * b))
            depth = -obstacle_distance(p0[j], p1[j], caps.radius[j], body.queries[o]).distance[0]
            assert depth == pytest.approx(c.depth, abs=1e-9) and depth > TOLERANCE
        brute = deepest_on_the_way(male50, a, b, body.queries, 150)
        clear = (d_a >= -TOLERANCE) & (d_b >= -TOLERANCE)  # inside at a frame: the frame's own rows report it
        for j, o in zip(*np.nonzero(clear & (brute > 2 * TOLERANCE)), strict=True):
            assert (caps.names[j], obstacles[o].name) in found, (caps.names[j], obstacles[o].name, brute[j, o])
        deep += int((clear & (brute > 2 * TOLERANCE)).sum())
    assert deep > 0  # the cases do cross


def test_a_hand_keyed_through_a_thin_plate_does_not_pass_through_it(tmp_path):
    """Frame 2 -> 3 moves the right hand 30 cm across a 1 cm plate. Unguarded, the frame's solution lies beyond the
    plate and the way there crosses it; detected only, the frame names the crossing and is not converged; guarded,
    the frame is re-solved and the way Blender plays (linear joint interpolation) stays out of the plate."""
    bare = plate_motion(tmp_path, plate=False)
    free = list(solve_frames(bare.problem_at, bare.frames, bare.start, bare.options, bare.limits))
    theta_2, theta_3 = free[1][1].theta, free[2][1].theta
    assert deepest_part(bare.model, theta_2, theta_3, PLATE_BOX, "hand_r") > 0.02  # the jump is real

    sc = plate_motion(tmp_path, plate=True)
    told = MotionSweep(resolve=False)
    reported = list(solve_frames(sc.problem_at, sc.frames, sc.start, sc.options, sc.limits, sweep=told))
    last = reported[-1][1]
    assert not last.converged
    assert "hand_r passes through plate between frames 2 and 3" in last.unmet
    assert "hand_r passes through plate between frames 2 and 3" in last.broken
    assert last.verdict().startswith("NOT held")
    assert any("mm deep at frame 2." in note for note in last.notes)

    guard = MotionSweep()
    guarded = list(solve_frames(sc.problem_at, sc.frames, sc.start, sc.options, sc.limits, sweep=guard))
    theta_2, theta_3 = guarded[1][1].theta, guarded[2][1].theta
    assert deepest_on_the_way(sc.model, theta_2, theta_3, [PLATE_BOX]).max() < 2 * TOLERANCE
    frame_3 = guarded[2][1]
    assert any("re-solved in" in note and "hand_r through plate" in note for note in frame_3.notes)
    assert guard.substeps > 0
    assert not any("passes through" in name for name in frame_3.unmet)


def test_the_target_held_behind_the_plate_stays_blocked(tmp_path):
    """The hand target stays beyond the plate for frames 3..5: each frame's first solution jumps through again and
    is held on the near side; every way from frame to frame stays out of the plate."""
    sc = plate_motion(tmp_path, plate=True, end=5)
    results = list(solve_frames(sc.problem_at, sc.frames, sc.start, sc.options, sc.limits))
    thetas = [r.theta for _, r in results]
    for a, b in zip(thetas[1:], thetas[2:], strict=False):
        assert deepest_on_the_way(sc.model, a, b, [PLATE_BOX], 100).max() < 2 * TOLERANCE
    assert all("hand_r" in r.unmet and not r.converged for _, r in results[2:])  # short of the target, not through


def lift_with_a_cabinet_behind(tmp_path: Path, trunk: float, frames: int = 200) -> tuple[list, MotionSweep]:
    """The box lift spread over ``frames`` frames, a cabinet 1 m behind the manikin, comfort ``trunk`` weight: the
    frames and the sweep that checked them."""
    data = long_motion(frames)
    data["obstacles"] = [dict(name="cabinet", kind="box", center=[0.0, 1.0, 0.8], size=[1.0, 0.4, 1.6])]
    data["comfort"] = {"trunk": trunk}
    path = tmp_path / f"lift_{trunk}_{frames}.toml"
    path.write_text(dumps_toml(data), encoding="utf-8")
    sc = load_scenario(path)
    sweep = MotionSweep()
    return list(solve_frames(sc.problem_at, sc.frames, sc.start, sc.options, sc.limits, sweep=sweep)), sweep


def test_a_motion_with_nothing_near_does_no_sub_sampling(tmp_path):
    """The standard model (trunk 0) stoops over the shelf with the arms clear of the body: lower bounds from the
    last queried pose certify most frames without a query, and no way is ever sub-sampled or re-solved. The
    behaviour model (the default) squats with the forearms near the thighs, so some ways are sampled there; still
    every frame converges and none is re-solved."""
    results, sweep = lift_with_a_cabinet_behind(tmp_path, 0.0)
    assert all(r.converged for _, r in results)
    assert sweep.samples == 0 and sweep.substeps == 0
    assert sweep.queries < len(results) / 2
    results, sweep = lift_with_a_cabinet_behind(tmp_path, BEHAVIOUR.trunk)
    assert all(r.converged for _, r in results) and sweep.substeps == 0


@pytest.mark.parametrize("seed", [0, *(pytest.param(s, marks=pytest.mark.slow) for s in range(1, 3))])  # ~2 s each
def test_swept_check_of_the_body_itself_agrees_with_brute_force_sampling(male50, seed):
    """Random large motions checked for the body's own pairs (hands and forearms vs trunk, head and thighs; the
    shanks): every pair that dense sampling finds deeper than 2 tol past its least distance (and clear at both ends)
    is reported, under its two parts' names, and every reported crossing is that deep where it says."""
    rng = np.random.default_rng(300 + seed)
    caps = capsules_of(male50)
    own = self_pairs(male50, caps)
    body = SweptBody(male50, [], np.zeros((len(caps), 0)), own=own)
    deep = 0
    for _ in range(12):
        a, b = random_pair(male50, rng, 1.0)
        pa, pb = body.pose(a), body.pose(b)
        d_a, d_b = body.distances(pa, 0.05), body.distances(pb, 0.05)
        report = body.check(pa, pb, d_a, d_b, 0.05)
        found = {(c.part, c.obstacle) for c in report.crossings}
        pairs = list(zip(own.first, own.second, strict=True))
        for c in report.crossings:
            i, j = caps.names.index(c.part), caps.names.index(c.obstacle)
            p0, p1 = caps.world(male50.forward((1 - c.s) * a + c.s * b))
            depth = own.least[pairs.index((i, j))] - capsule_pairs(p0, p1, caps.radius, [i], [j]).distance[0]
            assert depth == pytest.approx(c.depth, abs=1e-9) and depth > TOLERANCE
        worst = np.full(len(own), -np.inf)
        for s in np.linspace(0.0, 1.0, 300):
            p0, p1 = caps.world(male50.forward((1 - s) * a + s * b))
            worst = np.maximum(worst, own.least - capsule_pairs(p0, p1, caps.radius, own.first, own.second).distance)
        ends = np.minimum(d_a[own.first, np.arange(len(own))], d_b[own.first, np.arange(len(own))])
        for m in np.flatnonzero((ends >= -TOLERANCE) & (worst > 2 * TOLERANCE)):
            assert (caps.names[own.first[m]], caps.names[own.second[m]]) in found, (m, worst[m])
            deep += 1
    assert deep > 0  # the cases do cross


def squat_between(model, right_foot_y: float = 0.0) -> tuple[Problem, Problem]:
    """Two frames with the behaviour model (trunk 5): the hands at 0.25 m in front of the feet (solved from the
    crouched start: a squat), then standing with them at 1.0 m; the left foot planted in both, the right foot at
    ``right_foot_y`` m in the second."""

    def at(height: float, y_r: float) -> Problem:
        feet = [Target(f"foot_{s}", np.array([x, y, 0.0]), lock=("z", "rx", "ry"), support=True)
                for s, x, y in (("r", -0.083, y_r), ("l", 0.083, 0.0))]  # fmt: skip
        hands = [Target(f"hand_{s}", np.array([x, -0.35, height]), lock=("x", "y", "z")) for s, x in
                 (("r", -0.2), ("l", 0.2))]  # fmt: skip
        return Problem(model, ProblemSpec(feet + hands, comfort_weights=BEHAVIOUR))

    return at(0.25, 0.0), at(1.0, right_foot_y)


def test_a_squatting_planted_legs_way_is_not_flagged_through_the_floor(male50):
    """Both feet planted, rising from a squat: on the joint-linear way a straightening leg's shank dips through the
    floor (the foot leaves its place midway), which the body does not do; the planted legs are left out of the floor
    check, and the frame is clear."""
    before, after = squat_between(male50)
    frames = {1: before, 2: after}
    results = dict(solve_frames(frames.get, [1, 2], before.start(None), limits=None,
                                sweep=MotionSweep(resolve=False)))  # fmt: skip
    assert results[1].converged
    assert min(results[1].theta[male50.joint_index(f"knee_{s}_flexion")] for s in "rl") > np.radians(45)  # it squats
    assert results[2].converged, results[2].unmet
    assert not any("floor" in u for u in results[2].unmet)


def test_a_leg_whose_foot_moves_is_still_checked_against_the_floor(male50):
    """The right foot steps 20 cm between the frames: its leg keeps its floor pairs; the planted left leg does not."""
    sweep = MotionSweep()
    moved = squat_between(male50, right_foot_y=-0.2)
    assert planted_parts(*moved) == ("thigh_l", "shank_l", "foot_l")
    assert set(planted_parts(*squat_between(male50))) == {"thigh_r", "shank_r", "foot_r", "thigh_l", "shank_l",
                                                          "foot_l"}  # fmt: skip
    body = sweep.body(moved[1], planted_parts(*moved))
    floor = [i for i, o in enumerate(body.obstacles) if o.name == "floor"][0]
    caps = capsules_of(male50).names
    assert all(body.pairs[caps.index(p), floor] for p in ("thigh_r", "shank_r", "pelvis", "hand_r"))
    assert not any(body.pairs[caps.index(p), floor] for p in ("thigh_l", "shank_l", "foot_l", "foot_r"))


def test_what_the_sweep_keeps_from_frame_to_frame_is_what_it_computes_afresh(tmp_path, monkeypatch):
    """MotionSweep keeps from the last frame the planted parts (the same support targets), the bound from the
    anchor to this frame's start (the last frame's to its end), the carried box's placements and corners; it takes
    a frame's end pose from the result's kinematics and its box's placement from the result's state. Over the
    200-frame lift (a carried box, a cabinet) each is what computing it afresh gives, the same numbers (the same
    functions of the same inputs), and each shortcut is taken."""
    taken = {"bounds": 0, "pose": 0, "planted": 0, "box": 0}
    bounds, pose, box_at, planted = MotionSweep._bounds, MotionSweep._pose, MotionSweep._box_at, MotionSweep.planted
    travel = between_frames._corner_travel

    def fresh_bounds(self, body, p, a, b):
        taken["bounds"] += self._way is not None and self._way[1] is p and self._way[2] is a
        got = bounds(self, body, p, a, b)
        assert np.array_equal(np.array(got), body.bounds([(p, a), (p, b), (a, b)]))
        return got

    def fresh_pose(self, body, theta, at=None):
        taken["pose"] += at is not None and (body, theta.tobytes()) not in self._poses
        got, afresh = pose(self, body, theta, at), body.pose(theta)
        assert all(np.array_equal(x, y) for x, y in zip(got, afresh, strict=True))
        return got

    def fresh_box_at(self, problem, theta, at=None):
        taken["box"] += at is not None
        rows, got = problem.carried_obstacle_constraint, box_at(self, problem, theta, at)
        placed = carried_frame(*(problem.model.forward(theta).tcp_frame(tcp)[1] for tcp in rows.tcps))
        assert all(np.array_equal(x, y) for x, y in zip(got, (*placed, box_corners(*placed, rows.half)), strict=True))
        return got

    def fresh_travel(start, end):
        got = travel(start, end)
        assert got == float(np.linalg.norm(end - start, axis=1).max())
        return got

    def fresh_planted(self, before, after):
        taken["planted"] += self._planted is not None
        got = planted(self, before, after)
        assert got == planted_parts(before, after)
        return got

    for name, spy in (("_bounds", fresh_bounds), ("_pose", fresh_pose), ("_box_at", fresh_box_at),
                      ("planted", fresh_planted)):  # fmt: skip
        monkeypatch.setattr(MotionSweep, name, spy)
    monkeypatch.setattr(between_frames, "_corner_travel", fresh_travel)
    results, sweep = lift_with_a_cabinet_behind(tmp_path, 0.0)
    assert all(r.converged for _, r in results) and min(taken.values()) > len(results) / 2, taken
    check = MotionSweep.check
    monkeypatch.setattr(MotionSweep, "check", lambda self, body, a, b, at_b=None: check(self, body, a, b))
    again, swept = lift_with_a_cabinet_behind(tmp_path, 0.0)  # no end state given: the path-bound pre-test first
    assert (swept.queries, swept.samples) == (sweep.queries, sweep.samples)
    assert all(np.array_equal(r.x, s.x) and r.unmet == s.unmet for (_, r), (_, s) in zip(results, again, strict=True))


def test_a_frame_that_did_not_move_again_is_what_checking_it_afresh_gives(tmp_path, monkeypatch):
    """A long motion's frame whose solution stays where the last one ended (its targets moved within their
    tolerance) asks the sweep the same way again: the same anchor, the same start and end poses. The sweep then returns
    the certificate it found the last time, and the travel of the carried box's corners it measured. Over the lift
    spread over 500 frames each shortcut is taken, each is what computing it afresh gives (the anchor's bounds certify
    the way; a new sweep finds the same crossings of the box), and with the shortcuts off the motion queries, samples
    and solves the same."""
    taken = {"certified": 0, "travel": 0}
    check, carried = MotionSweep.check, MotionSweep.carried_crossings

    def fresh_check(self, body, theta_a, theta_b, at_b=None):
        last, anchor = self._certified, self._anchor
        got = check(self, body, theta_a, theta_b, at_b)
        if last is not None and last[0] is anchor and last[1] is self._pose(body, theta_a) and last[2] is got.b:
            taken["certified"] += 1
            _, p, d_p = anchor
            a, b = last[1], last[2]
            assert not body.any_uncertain(d_p, *body.bounds([(p, a), (p, b), (a, b)])) and not got.crossings
        return got

    def fresh_carried(self, problem, theta_a, theta_b, at_b=None):
        last = self._travel
        got = carried(self, problem, theta_a, theta_b, at_b)
        if last is not None and self._travel is last:
            taken["travel"] += 1
            start, end = (MotionSweep()._box_at(problem, theta)[2] for theta in (theta_a, theta_b))
            assert last[2] == between_frames._corner_travel(start, end)
            assert got == MotionSweep().carried_crossings(problem, theta_a, theta_b)
        return got

    monkeypatch.setattr(MotionSweep, "check", fresh_check)
    monkeypatch.setattr(MotionSweep, "carried_crossings", fresh_carried)
    results, sweep = lift_with_a_cabinet_behind(tmp_path, BEHAVIOUR.trunk, frames=500)
    assert min(taken.values()) > 10, taken
    monkeypatch.setattr(MotionSweep, "_certified", property(lambda self: None, lambda self, value: None), raising=False)
    monkeypatch.setattr(MotionSweep, "_travel", property(lambda self: None, lambda self, value: None), raising=False)
    again, swept = lift_with_a_cabinet_behind(tmp_path, BEHAVIOUR.trunk, frames=500)  # every way checked afresh
    assert (swept.queries, swept.samples) == (sweep.queries, sweep.samples)
    assert all(np.array_equal(r.x, s.x) and r.unmet == s.unmet for (_, r), (_, s) in zip(results, again, strict=True))


def test_the_planted_parts_kept_follow_the_supports(male50):
    """The planted parts kept for the same support targets are those of the two problems asked for, as the feet
    stay, step and come back."""
    squat, step = squat_between(male50), squat_between(male50, right_foot_y=-0.2)
    sweep = MotionSweep()
    for before, after in (squat, squat, step, step, (step[1], squat[1]), squat, (squat[0], step[1])):
        parts = sweep.planted(before, after)
        assert parts == planted_parts(before, after)
        np.testing.assert_array_equal(sweep.body(after, parts).pairs, MotionSweep().body(after, parts).pairs)


def test_the_planted_parts_kept_follow_supports_read_again(male50, monkeypatch):
    """Support targets read again (new objects, as a bake reads the scene every frame) at the same frames keep the
    planted parts; moved ones do not."""
    squat, step = squat_between(male50), squat_between(male50, right_foot_y=-0.2)
    asked = []
    monkeypatch.setattr(between_frames, "planted_parts", lambda *a: asked.append(1) or planted_parts(*a))

    def again(problem):  # the same targets as new objects with copied arrays
        return problem.with_targets([dataclasses.replace(t, position=np.array(t.position, dtype=float))
                                     for t in problem.all_targets])  # fmt: skip

    sweep = MotionSweep()
    for before, after in (squat, (again(squat[0]), again(squat[1])), step, (again(step[0]), again(step[1]))):
        parts = sweep.planted(before, after)
        assert parts == planted_parts(before, after)
    assert len(asked) == 2  # the squat's and the step's: the targets read again were known
