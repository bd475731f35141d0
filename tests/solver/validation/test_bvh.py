"""The BVH reader against hand-written files with known answers: hierarchy, offsets, channel orders, rotations
composed in file order, End Sites, the root's translation."""

from __future__ import annotations

import numpy as np
import pytest

from solver.errors import ScenarioError
from solver.validation.bvh import axis_rotation, channel_transform, parse_bvh, read_bvh

TWO_LINKS = """HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
  JOINT Arm
  {
    OFFSET 1 0 0
    CHANNELS 3 Xrotation Yrotation Zrotation
    End Site
    {
      OFFSET 2 0 0
    }
  }
}
MOTION
Frames: 3
Frame Time: 0.5
0 0 0 0 0 0 0 0 0
10 20 30 90 0 0 0 0 0
0 0 0 0 0 0 0 0 90
"""


def test_hierarchy_offsets_and_channels() -> None:
    b = parse_bvh(TWO_LINKS)
    assert [j.name for j in b.joints] == ["Hips", "Arm"]
    assert b.joints[1].parent == 0
    assert b.joints[1].offset == pytest.approx([1, 0, 0])
    assert b.joints[0].rotation_order == "ZYX"
    assert b.joints[1].rotation_order == "XYZ"
    assert b.joints[1].end == pytest.approx([2, 0, 0])
    assert b.frames.shape == (3, 9)
    assert b.frame_time == pytest.approx(0.5)


def test_rest_pose_and_root_translation() -> None:
    b = parse_bvh(TWO_LINKS)
    rot, pts = b.pose(0)
    assert pts[1] == pytest.approx([1, 0, 0])
    assert b.end_point("Arm", rot, pts) == pytest.approx([3, 0, 0])
    rot, pts = b.pose(1)  # root moved to (10, 20, 30) and turned 90 deg about z: x -> y
    assert pts[0] == pytest.approx([10, 20, 30])
    assert pts[1] == pytest.approx([10, 21, 30])
    assert b.end_point("Arm", rot, pts) == pytest.approx([10, 23, 30])


def test_child_rotation_turns_only_what_follows() -> None:
    rot, pts = parse_bvh(TWO_LINKS).pose(2)  # the arm turns 90 deg about z at its joint
    assert pts[1] == pytest.approx([1, 0, 0])
    assert parse_bvh(TWO_LINKS).end_point("Arm", rot, pts) == pytest.approx([1, 2, 0])


def test_channel_order_is_the_file_order() -> None:
    # Z then X (intrinsic): R = Rz(90) @ Rx(90); X then Z: R = Rx(90) @ Rz(90): they differ
    zx, _ = channel_transform(("Zrotation", "Xrotation"), np.array([90.0, 90.0]))
    xz, _ = channel_transform(("Xrotation", "Zrotation"), np.array([90.0, 90.0]))
    assert zx == pytest.approx(axis_rotation("Z", 90) @ axis_rotation("X", 90))
    assert xz == pytest.approx(axis_rotation("X", 90) @ axis_rotation("Z", 90))
    assert zx @ np.array([0.0, 1.0, 0.0]) == pytest.approx([0, 0, 1], abs=1e-12)  # y -> z by X, then z stays
    assert xz @ np.array([0.0, 1.0, 0.0]) == pytest.approx([-1, 0, 0], abs=1e-12)  # y -> -x by Z, then X keeps x


def test_axis_rotation_is_right_handed() -> None:
    assert axis_rotation("X", 90) @ np.array([0.0, 1.0, 0.0]) == pytest.approx([0, 0, 1], abs=1e-12)
    assert axis_rotation("Y", 90) @ np.array([0.0, 0.0, 1.0]) == pytest.approx([1, 0, 0], abs=1e-12)
    assert axis_rotation("Z", 90) @ np.array([1.0, 0.0, 0.0]) == pytest.approx([0, 1, 0], abs=1e-12)


def test_a_short_motion_section_is_refused(tmp_path) -> None:
    bad = tmp_path / "bad.bvh"
    bad.write_text(TWO_LINKS.replace("Frames: 3", "Frames: 4"))
    with pytest.raises(ScenarioError, match="bad.bvh"):
        read_bvh(bad)
