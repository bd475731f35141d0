"""What the manikin's feet may do and what they did (no bpy): the Feet setting's locks, how far each support moved
in a solve, and the hints for a support that is off the floor or pushed off its target by an obstacle.

Feet "Planted" (the default) solves each support with its own locks, and a support the add-on makes locks all six
axes, so the feet stay where they are; "May slide" frees every support's x, y and rz (it slides and turns on its
plane; its z, rx, ry locks stay as set), without bounds: any support, a hand on a rail as well as a foot. "May step"
frees the feet alone, as a person steps (:mod:`solver.stance`: each within a step of its target, not crossed, turned
at most 45 deg, a step cost so it steps only as far as that helps) and reports each step (length, direction, turn)
instead of a slide. Either way a support that ended away from its target is reported.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ...solver.options import AXES

if TYPE_CHECKING:
    from ...solver import Result

PLANTED, SLIDE, STEP = "PLANTED", "SLIDE", "STEP"
SLIDE_FREE = ("x", "y", "rz")  # what "May slide" frees on every support: along and about its plane
MOVED_MM, MOVED_DEG = 1.0, 1.0  # below these a support counts as where its target is (the solver's tolerances)
OFF_FLOOR_MM = 5.0  # a support target farther than this from the floor plane z = 0 is noted


def solved_lock(lock: tuple[str, ...], support: bool, feet: str) -> tuple[str, ...]:
    """The axes a target is solved with: its own ``lock``, but for a support under Feet = May slide without
    x, y and rz."""
    if support and feet == SLIDE:
        return tuple(a for a in lock if a not in SLIDE_FREE)
    return tuple(a for a in AXES if a in lock)


def may_slide(lock: tuple[str, ...]) -> bool:
    """A support with these locks can slide or turn (one of x, y, rz unlocked)."""
    return any(a not in lock for a in SLIDE_FREE)


def moved_supports(result: Result) -> dict[str, dict[str, float]]:
    """Each enabled support whose TCP ended away from its target: {tcp: {"mm": distance, "deg": turn, "held": 1.0
    if its locked axes are met (it slid on purpose), 0.0 if it was not held}} (more than 1 mm or 1 deg off)."""
    problem = result.problem
    kin = result.state.kin
    out = {}
    for t in problem.all_targets:
        if not (t.support and t.enabled):
            continue
        rot, pos = kin.tcp_frame(problem.model.tcp(t.tcp))
        mm = 1e3 * float(np.linalg.norm(pos - np.asarray(t.position)))
        deg = 0.0
        if t.rotation is not None:
            cos = (np.trace(np.asarray(t.rotation).T @ rot) - 1.0) / 2.0
            deg = float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
        if mm > MOVED_MM or deg > MOVED_DEG:
            out[t.tcp] = {"mm": mm, "deg": deg, "held": float(t.tcp not in result.broken)}
    return out


def moved_text(moved: dict[str, dict[str, float]]) -> list[str]:
    """ "foot_r slid 412 mm", "foot_l turned 12 deg", "foot_l slid 20 mm, turned 3 deg" (a support not held: "foot_l
    is 556 mm, 5 deg off its target"): one per moved support."""
    lines = []
    for tcp, m in moved.items():
        held = m.get("held", 1.0) > 0.0
        parts = [f"{'slid ' if held else ''}{m['mm']:.0f} mm"] if m["mm"] > MOVED_MM else []
        parts += [f"{'turned ' if held else ''}{m['deg']:.0f} deg"] if m["deg"] > MOVED_DEG else []
        lines.append(f"{tcp} " + ", ".join(parts) if held else f"{tcp} is {', '.join(parts)} off its target")
    return lines


def floor_notes(result: Result) -> list[str]:
    """A hint for each enabled support target off the floor (z = 0 of the manikin's frame, i.e. its armature's
    origin) by more than 5 mm: below it cannot be held with Floor on; above it stands on nothing but what is there."""
    notes = []
    for t in result.problem.all_targets:
        z_mm = 1e3 * float(np.asarray(t.position)[2])
        if not (t.support and t.enabled) or abs(z_mm) <= OFF_FLOOR_MM:
            continue
        if z_mm < 0.0:
            notes.append(f"{t.tcp}: its support target is {-z_mm:.0f} mm below the manikin's floor (the armature's "
                         "origin): move the target up, or move the manikin down to it (targets parented to the "
                         "manikin move with it)")  # fmt: skip
        else:
            notes.append(f"{t.tcp}: its support target is {z_mm:.0f} mm above the manikin's floor (the armature's "
                         "origin), standing on nothing unless a platform is there: move the manikin onto the platform "
                         "instead, or move the target down")  # fmt: skip
    return notes


def pushed_notes(result: Result) -> list[str]:
    """For each support not held (priority 1): the obstacles touching its foot (within their clearance + 1 mm), or
    else those touching any body part, named with a hint."""
    problem = result.problem
    supports = {t.tcp for t in problem.all_targets if t.support and t.enabled}
    touching = [c for c in result.closest if c.other != "floor" and c.distance <= c.clearance + 1e-3]
    body = set(problem.model.link_names)
    touching = [c for c in touching if c.other not in body]
    notes = []
    for name in result.broken:
        if name not in supports:
            continue
        link = problem.model.link_names[problem.model.tcp(name).link]
        own = sorted({c.other for c in touching if c.part.split(".")[0] == link})
        near = own or sorted({c.other for c in touching})
        if not near:
            continue
        how = "pushes it off its target" if own else "touches the body and may keep it from its target"
        names = ", ".join(repr(n) for n in near)
        notes.append(f"{name} NOT held: obstacle {names} {how}; move the obstacle or the target, lower its clearance,"
                     " or give it a closed shape (a Plane is an endless half-space)")  # fmt: skip
    return notes
