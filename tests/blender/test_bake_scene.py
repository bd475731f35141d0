"""A bake follows an animated scene frame by frame (tests/blender/bake_scene_session.py in a subprocess): what a
Baker reads once (problem_io.Held: the obstacle objects, meshes nothing can change, the model, the linked empties)
gives each frame the problem Solve Pose reads from scratch there, and keyed obstacles (location, modifier, shape
key, parent, Obstacle toggle, clearance) and a keyed target setting are followed."""

from __future__ import annotations

import numpy as np
import pytest

FRAMES = [str(f) for f in range(1, 7)]
EXACT = 1e-9  # m: the same reads of the same float32 numbers


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("bake_scene"), "bake_scene_session.py")


def _bounds(session: dict, frame: str, name: str) -> np.ndarray:
    return np.array(session["baked"][frame]["obstacles"][name]["bounds"])


def test_each_baked_frame_reads_what_solve_pose_reads_there(session: dict) -> None:
    assert all(session["converged"])
    for frame in FRAMES:
        baked, fresh = session["baked"][frame], session["fresh"][frame]
        assert sorted(baked["obstacles"]) == sorted(fresh["obstacles"]), frame
        for name, ob in baked["obstacles"].items():
            again = fresh["obstacles"][name]
            assert (ob["kind"], ob["clearance"]) == (again["kind"], again["clearance"]), (frame, name)
            np.testing.assert_allclose(ob["bounds"], again["bounds"], rtol=0.0, atol=EXACT, err_msg=f"{frame} {name}")
        assert baked["weights"] == pytest.approx(fresh["weights"], abs=1e-12)


def test_only_meshes_nothing_can_change_are_read_once(session: dict) -> None:
    fixed = session["fixed"]
    assert fixed["moved"] and fixed["child"] and fixed["still"] and fixed["still mesh"] and fixed["switched"]
    assert not fixed["displaced"] and not fixed["stretched"]  # a modifier, shape keys: read every frame
    assert not fixed["male_50.body"]  # the skinned body (never an obstacle here) is deformed by its armature


def test_keyed_obstacles_move_frame_by_frame(session: dict) -> None:
    first, last = "1", FRAMES[-1]
    np.testing.assert_allclose(_bounds(session, last, "moved") - _bounds(session, first, "moved"),
                               [[0.0, 1.0, 0.0]] * 2, atol=1e-5)  # fmt: skip
    np.testing.assert_allclose(_bounds(session, last, "child") - _bounds(session, first, "child"),
                               [[0.0, 0.0, 0.8]] * 2, atol=1e-5)  # fmt: skip
    lift = [_bounds(session, f, "displaced")[:, 2] - _bounds(session, first, "displaced")[:, 2] for f in FRAMES]
    np.testing.assert_allclose(lift[-1], [0.5, 0.5], atol=1e-5)  # the modifier's keyed strength
    top = [_bounds(session, f, "stretched")[1, 2] for f in FRAMES]
    assert top[-1] - top[0] == pytest.approx(0.6, abs=1e-5)  # the keyed shape key
    for name, series in (("displaced", [d[1] for d in lift]), ("stretched", top)):
        assert all(b > a for a, b in zip(series, series[1:], strict=False)), (name, series)  # moved every frame


def test_keyed_settings_are_read_every_frame(session: dict) -> None:
    baked = session["baked"]
    assert [("switched" in baked[f]["obstacles"]) for f in FRAMES] == [True] * 3 + [False] * 3
    assert baked["1"]["obstacles"]["switched"]["clearance"] == pytest.approx(0.01)
    assert baked["3"]["obstacles"]["switched"]["clearance"] == pytest.approx(0.05)
    weights = [baked[f]["weights"]["hand_r"] for f in FRAMES]
    assert weights[0] == pytest.approx(1.0) and weights[-1] == pytest.approx(3.0)
    assert all(b > a for a, b in zip(weights, weights[1:], strict=False))


def test_what_does_not_move_is_the_same_object_every_frame(session: dict) -> None:
    """An unmoved obstacle is the very same shape, an unmoved target the very same Target: the solver keeps what
    it built for them."""
    baked = session["baked"]
    for name in ("still", "still mesh"):
        assert len({baked[f]["obstacles"][name]["id"] for f in FRAMES}) == 1, name
    assert len({baked[f]["obstacles"]["moved"]["id"] for f in FRAMES}) == len(FRAMES)
    for tcp in ("foot_l", "foot_r"):
        assert len({baked[f]["targets"][tcp] for f in FRAMES[1:]}) == 1, tcp


def test_a_mesh_a_frame_change_handler_edits_is_read_every_frame(session: dict) -> None:
    """With a frame change handler (a script may edit any mesh there) even a plain mesh is read every frame."""
    scripted = session["scripted"]
    assert scripted["fixed"] == [False]
    for frame in FRAMES:
        assert scripted["tops"][frame] == pytest.approx(0.5 + 0.2 + 0.05 * int(frame), abs=1e-5), frame
