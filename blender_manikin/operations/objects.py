"""Objects of operations in the scene (bpy): a mesh marked as an object is the box of its mesh's bounds in its own
axes (as an obstacle of shape Box is), its mass from its settings, its grasps from its child empties.

Grasp empties: a child empty named ``grasp_r`` / ``grasp_l`` is the right / left hand's frame of the grasp "grasp",
``grasp_NAME_r`` / ``grasp_NAME_l`` of the grasp NAME (Blender's ".001" suffixes are ignored). The empty's axes
are the hand TCP's: its z axis is the palm normal, pointing into the object (``solver.operations.objects``). A
grasp with both hands is also offered to each hand alone ("NAME right", "NAME left"), so a one-handed get finds
it; two-handed grasps come first. :func:`propose_grasps` makes the solver's proposal (both palms on the side faces
at mid height) as such empties, for the user to move.
"""

from __future__ import annotations

import bpy
import numpy as np
from mathutils import Matrix

from ...solver.body.spatial import matrix_to_quat
from ...solver.collision.placed import shape_from_bounds
from ...solver.io.scenario.obstacles import obstacle_table
from .properties import GRASP, is_work_object

TCPS = {"r": "hand_r", "l": "hand_l"}
EMPTY_SIZE = 0.06  # m: the grasp empties' arrows


def work_objects(scene: bpy.types.Scene) -> list[bpy.types.Object]:
    """The scene's objects of operations, by name."""
    return sorted((ob for ob in scene.objects if is_work_object(ob)), key=lambda ob: ob.name)


def box_of(ob: bpy.types.Object, to_local: np.ndarray):
    """The object's box (``solver.collision.Box``) in the space ``to_local`` (4x4) maps the world into (m)."""
    points = np.array([v.co[:] for v in ob.data.vertices], dtype=float).reshape(-1, 3)
    if not len(points):
        from ...solver.errors import UsageError

        raise UsageError(f"object {ob.name!r}: its mesh has no vertices")
    world = to_local @ np.array(ob.matrix_world)
    return shape_from_bounds("box", world, points.min(axis=0), points.max(axis=0), name=ob.name)


def _unscaled(m: np.ndarray) -> np.ndarray:
    rotation = m[:3, :3] / np.linalg.norm(m[:3, :3], axis=0)
    u, _, vt = np.linalg.svd(rotation)  # the nearest rotation (an empty sheared by its parent's scale)
    return u @ vt


def grasp_tables(ob: bpy.types.Object, box, to_local: np.ndarray) -> list[dict]:
    """``[[objects.grasps]]`` of ``ob``'s child empties (``box``: its box in the same space as ``to_local``)."""
    pairs: dict[str, dict] = {}
    for child in sorted(ob.children, key=lambda c: c.name):
        found = GRASP.match(child.name)
        if child.type != "EMPTY" or found is None:
            continue
        m = to_local @ np.array(child.matrix_world)
        rb = np.asarray(box.rotation)
        position = rb.T @ (m[:3, 3] - np.asarray(box.center))
        rotation = rb.T @ _unscaled(m)
        # no lock: the schema's default, all six axes: the hand as the empty is
        frame = dict(position=[float(v) for v in position], rotation=[float(v) for v in matrix_to_quat(rotation)])
        pairs.setdefault(found["name"] or "grasp", {})[TCPS[found["hand"]]] = frame
    both = [dict(name=name, **hands) for name, hands in pairs.items() if len(hands) == 2]
    single = [dict(name=f"{name} {'right' if tcp == 'hand_r' else 'left'}" if len(hands) == 2 else name,
                   **{tcp: frame}) for name, hands in pairs.items() for tcp, frame in hands.items()]  # fmt: skip
    return both + single


def object_table(ob: bpy.types.Object, to_local: np.ndarray) -> dict:
    """The ``[[objects]]`` table of ``ob`` (its box, mass and grasps; none: the solver proposes them)."""
    box = box_of(ob, to_local)
    table = obstacle_table(box) | {"mass": float(f"{ob.manikin_object.mass:.7g}")}
    grasps = grasp_tables(ob, box, to_local)
    if grasps:
        table["grasps"] = grasps
    return table


def propose_grasps(ob: bpy.types.Object) -> list[bpy.types.Object]:
    """The solver's proposed two-handed grasp of ``ob`` as child empties ``grasp_r`` and ``grasp_l`` (an earlier
    proposal's empties replaced; other grasp empties stay); the empties made."""
    from ...solver.operations.objects import WorkObject
    from ...solver.operations.objects import propose_grasps as proposed

    box = box_of(ob, np.eye(4))  # in world space: a grasp is the same in the object's frame in any space
    grasp = proposed(WorkObject(ob.name, box, ob.manikin_object.mass))["both sides"]
    for child in list(ob.children):
        found = GRASP.match(child.name)
        if child.type == "EMPTY" and found is not None and found["name"] is None:
            bpy.data.objects.remove(child, do_unlink=True)
    made = []
    rb, centre = np.asarray(box.rotation), np.asarray(box.center)
    collection = ob.users_collection[0] if ob.users_collection else bpy.context.scene.collection
    for tcp, hand in grasp.hands.items():
        empty = bpy.data.objects.new(f"grasp_{tcp[-1]}", None)
        empty.empty_display_type, empty.empty_display_size = "ARROWS", EMPTY_SIZE
        collection.objects.link(empty)
        world = np.eye(4)
        world[:3, :3], world[:3, 3] = rb @ hand.rotation, centre + rb @ hand.position
        empty.parent = ob
        empty.matrix_world = Matrix(world.tolist())
        made.append(empty)
    return made
