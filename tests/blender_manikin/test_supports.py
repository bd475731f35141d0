"""The Feet setting and the support messages (blender_manikin/scene/supports.py, no bpy), on solver problems: planted
feet hold a reach too far short, May slide frees x, y, rz and the slide is measured in mm; a support off the floor
and a support pushed by an obstacle are named with a hint."""

from __future__ import annotations

import importlib
import importlib.util
import sys
from functools import cache
from pathlib import Path

import numpy as np

from solver import Problem, Result, Target, solve
from solver.collision import HalfSpace
from solver.io.scenario.bodies import load_preset
from solver.options import AXES

ROOT = Path(__file__).resolve().parents[2]


def _checkout_module(path: str, name: str = "manikin_checkout"):
    """``path`` of the checkout loaded as the package Blender loads the extension as (so the Blender layer's relative
    imports of the solver resolve; as in test_scores_follow_registry.py)."""
    if name not in sys.modules:
        root = str(ROOT)
        spec = importlib.util.spec_from_file_location(name, ROOT / "__init__.py", submodule_search_locations=[root])
        package = importlib.util.module_from_spec(spec)
        sys.modules[name] = package
        spec.loader.exec_module(package)
    return importlib.import_module(f"{name}.{path}")


supports = _checkout_module("blender_manikin.scene.supports")  # duck-typed on the Result: the top solver's will do
PLANTED, SLIDE, solved_lock, may_slide = supports.PLANTED, supports.SLIDE, supports.solved_lock, supports.may_slide
moved_supports, moved_text = supports.moved_supports, supports.moved_text
floor_notes, pushed_notes = supports.floor_notes, supports.pushed_notes


def test_solved_lock_frees_only_a_supports_plane_axes_when_sliding() -> None:
    assert solved_lock(AXES, True, PLANTED) == AXES
    assert solved_lock(AXES, True, SLIDE) == ("z", "rx", "ry")
    assert solved_lock(AXES, False, SLIDE) == AXES  # a reach target is no support: untouched
    assert solved_lock(("x", "y", "z"), True, SLIDE) == ("z",)  # the setting frees, never locks
    assert may_slide(("z", "rx", "ry")) and not may_slide(AXES)


@cache
def _model():
    return load_preset("male_50")


def _solve(feet: str, hand_shift=(0.0, -2.5, 0.0), foot_z: float = 0.0, obstacles=()) -> Result:
    """male_50 from its zero pose: both feet supports (their target ``foot_z`` m up), the right hand moved."""
    model = _model()
    x0 = model.zero_pose()
    kin = model.forward(x0)
    targets = []
    for tcp in ("foot_l", "foot_r"):
        rot, pos = kin.tcp_frame(model.tcp(tcp))
        targets.append(Target(tcp, pos + [0.0, 0.0, foot_z], rot, solved_lock(AXES, True, feet), support=True))
    rot, pos = kin.tcp_frame(model.tcp("hand_r"))
    targets.append(Target("hand_r", pos + np.array(hand_shift), rot, solved_lock(AXES, False, feet)))
    return solve(Problem(model, targets, [], [], True, obstacles=list(obstacles)), x0)


def test_planted_feet_stay_and_the_far_hand_ends_short() -> None:
    result = _solve(PLANTED)
    assert not result.converged and result.unmet == ["hand_r"] and result.broken == []
    assert moved_supports(result) == {} and moved_text({}) == []


def test_sliding_feet_converge_and_are_reported_in_mm() -> None:
    result = _solve(SLIDE)
    assert result.converged
    moved = moved_supports(result)
    assert sorted(moved) == ["foot_l", "foot_r"] and all(2000.0 < m["mm"] < 2600.0 for m in moved.values())
    assert all(m["held"] == 1.0 for m in moved.values())
    words = moved_text(moved)
    assert words[0].startswith("foot_l slid ") and words[0].split(",")[0].endswith(" mm")


def test_moved_text_says_slid_and_turned() -> None:
    assert moved_text({"foot_r": {"mm": 412.3, "deg": 0.2}}) == ["foot_r slid 412 mm"]
    assert moved_text({"foot_l": {"mm": 0.5, "deg": 12.0}}) == ["foot_l turned 12 deg"]
    assert moved_text({"foot_l": {"mm": 20.0, "deg": 3.0}}) == ["foot_l slid 20 mm, turned 3 deg"]
    assert moved_text({"foot_l": {"mm": 556.3, "deg": 5.0, "held": 0.0}}) == ["foot_l is 556 mm, 5 deg off its target"]


def test_a_support_below_the_floor_is_named_with_a_hint() -> None:
    result = _solve(PLANTED, hand_shift=(0.0, 0.0, 0.0), foot_z=-0.3)
    notes = floor_notes(result)
    assert len(notes) == 2 and notes[0].startswith("foot_l: its support target is 300 mm below the manikin's floor")
    assert "move the manikin down" in notes[0]
    above = floor_notes(_solve(PLANTED, hand_shift=(0.0, 0.0, 0.0), foot_z=0.2))
    assert above and "200 mm above" in above[0] and "platform" in above[0]
    assert floor_notes(_solve(PLANTED, hand_shift=(0.0, 0.0, 0.0))) == []


def test_an_obstacle_pushing_the_feet_is_named() -> None:
    table = HalfSpace([0.0, 0.0, 0.75], [0.0, 0.0, 1.0], name="table top")  # a plane obstacle: everything below
    result = _solve(PLANTED, hand_shift=(0.0, 0.0, 0.0), obstacles=[table])
    assert {"foot_l", "foot_r"} <= set(result.broken)
    notes = pushed_notes(result)
    assert notes and all("obstacle 'table top'" in n for n in notes)
    assert all(m["held"] == 0.0 for m in moved_supports(result).values())  # pushed off: not "slid"
    assert {n.split()[0] for n in notes} == {"foot_l", "foot_r"}
