"""Creating the empties a user moves: ``target.<tcp>``, ``loop.<tcp>`` and ``load.<tcp>`` (bpy).

A target the user adds (Add Target, the feet of Add Manikin) is parented to the armature object, so moving the
manikin (G on the armature) carries its targets along, as it carries its bones; a target given no parent (a
scenario's, whose keys are world locations) stays in the world, and a user may re-parent any target (to a fixture,
or to nothing: Alt+P). Loops and loads are parented to a TCP empty so they travel with the pose. Each new empty
starts where it is already met (a target on its TCP's current frame, a loop at the current offset), so adding one
never jerks the pose.
"""

from __future__ import annotations

import bpy
import numpy as np
from mathutils import Matrix

from ...solver import ManikinError
from ...solver.body.model import GRAVITY
from ...solver.options import AXES
from .armature import model_of, read_x, tcp_world_frame
from .schema import member_name, members, tcp_empty

FEET = ("foot_l", "foot_r")
FOOT_LOCK = AXES  # planted: a foot holds where it stands; Feet = "May slide" frees x, y, rz (supports.py)


def _collection(arm: bpy.types.Object) -> bpy.types.Collection:
    return arm.users_collection[0] if arm.users_collection else bpy.context.scene.collection


def _check_tcp(arm: bpy.types.Object, tcp: str) -> None:
    model = model_of(arm)
    if tcp not in model.tcps:
        raise ManikinError(f"{arm.name} has no TCP {tcp!r} (known: {', '.join(sorted(model.tcps))})")


def find_member(arm: bpy.types.Object, role: str, tcp: str) -> bpy.types.Object | None:
    for ob in members(arm):
        if ob.manikin_target.role == role and ob.manikin_target.tcp == tcp:
            return ob
    return None


def _new_empty(arm: bpy.types.Object, name: str, role: str, tcp: str, display: str, size: float) -> bpy.types.Object:
    ob = bpy.data.objects.new(name, None)
    ob.empty_display_type = display
    ob.empty_display_size = size
    s = ob.manikin_target
    s.role, s.rig, s.tcp = role, arm, tcp
    _collection(arm).objects.link(ob)
    return ob


def add_target(
    arm: bpy.types.Object,
    tcp: str,
    lock: tuple[str, ...] = AXES,
    support: bool = False,
    friction: float = 0.6,
    follow: bool = False,
) -> bpy.types.Object:
    """A target for ``tcp`` on the TCP's current frame; an existing target of that TCP is snapped there instead.
    ``follow``: parent it to the armature object (it moves with the manikin), else it stays in the world."""
    _check_tcp(arm, tcp)
    ob = find_member(arm, "TARGET", tcp)
    if ob is None:
        ob = _new_empty(arm, member_name("TARGET", tcp), "TARGET", tcp, "ARROWS", 0.12)
        s = ob.manikin_target
        s.lock = [a in lock for a in AXES]
        s.support, s.friction = support, friction
    ob.parent = arm if follow else None
    ob.matrix_parent_inverse = Matrix.Identity(4)  # its location is then in the manikin's frame
    ob.matrix_world = tcp_world_frame(arm, read_x(arm), tcp)
    return ob


def add_default_supports(arm: bpy.types.Object) -> list[bpy.types.Object]:
    """Both feet on the floor as planted supports (all six axes locked), parented to the armature; a body without
    feet stands on its "floor" TCP (the snake), else on its first TCP."""
    model = model_of(arm)
    tcps = [t for t in FEET if t in model.tcps] or [t for t in ("floor",) if t in model.tcps] or list(model.tcps)[:1]
    return [add_target(arm, t, lock=FOOT_LOCK, support=True, follow=True) for t in tcps]


def _parent_to_tcp(ob: bpy.types.Object, arm: bpy.types.Object, tcp: str, world: Matrix) -> None:
    """Parent ``ob`` to the TCP empty (when there is one) keeping the world frame ``world``."""
    parent = tcp_empty(arm, tcp)
    ob.parent = parent
    ob.matrix_parent_inverse = Matrix.Identity(4)
    if parent is None:
        ob.matrix_world = world
    else:
        ob.matrix_basis = tcp_world_frame(arm, read_x(arm), tcp).inverted() @ world


def add_loop(arm: bpy.types.Object, tcp: str, other: str, lock: tuple[str, ...] = ("x", "y", "z")) -> bpy.types.Object:
    """Hold ``tcp`` at its current offset from ``other``: an empty parented to ``tcp.<other>``."""
    _check_tcp(arm, tcp)
    _check_tcp(arm, other)
    if tcp == other:
        raise ManikinError("a loop needs two different TCPs")
    ob = find_member(arm, "LOOP", tcp) or _new_empty(arm, member_name("LOOP", tcp), "LOOP", tcp, "SPHERE", 0.03)
    s = ob.manikin_target
    s.other = other
    s.lock = [a in lock for a in AXES]
    _parent_to_tcp(ob, arm, other, tcp_world_frame(arm, read_x(arm), tcp))
    return ob


def add_load(arm: bpy.types.Object, tcp: str, mass: float) -> bpy.types.Object:
    """A carried mass (kg) hanging at ``tcp``: its weight as a world-frame force, shown as a cube at the TCP."""
    _check_tcp(arm, tcp)
    if not (np.isfinite(mass) and mass >= 0.0):
        raise ManikinError(f"load mass must be a non-negative number of kg, got {mass}")
    ob = find_member(arm, "LOAD", tcp) or _new_empty(arm, member_name("LOAD", tcp), "LOAD", tcp, "CUBE", 0.05)
    ob.manikin_target.force = tuple(float(v) for v in mass * GRAVITY)
    _parent_to_tcp(ob, arm, tcp, tcp_world_frame(arm, read_x(arm), tcp))
    return ob
