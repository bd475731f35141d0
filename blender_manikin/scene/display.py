"""What shows a manikin's body (bpy): the skinned human, the collision capsules or the solids by segment mass.

Each is a mesh object parented to the armature, deformed by it (vertex groups named after the bones, an Armature
modifier), click-through, and tagged with the display it belongs to (``schema.DISPLAY_KEY``). The human is built
with the manikin (``<armature>.body``; a model without a human mesh, such as the snake, gets the solids there); the
capsules and solids are built the first time they are chosen. :func:`show` makes the chosen one visible in the
viewport and the render and hides the others.

The human: ``solver.bodymesh.fit_body`` (the MakeHuman mesh fitted onto the model), eyeballs and the twist split
(``rigging/skin.py``), smooth shaded, with a Subdivision modifier at level 1 for renders only (0 in the viewport,
so posing stays fast), and a skin material (Principled BSDF) shared by every manikin.
"""

from __future__ import annotations

import bpy
import numpy as np

from ...solver.body.model import Model
from ...solver.collision.body import capsules_of
from ...solver.errors import ModelError
from ..rigging.body_mesh import BodyMesh, build_body_mesh, capsule_mesh
from ..rigging.bones import RigLayout
from ..rigging.skin import SkinMesh, skin_mesh
from .compat import node_tree
from .schema import BODY_SUFFIX, DISPLAY_KEY, DISPLAY_SUFFIXES, EYE_MATERIALS, SHADED_KEY, SKIN_MATERIAL

MODES = ("HUMAN", "CAPSULES", "SOLIDS")
SKIN_COLOR = (0.78, 0.5, 0.38)  # linear RGB
SKIN_ROUGHNESS = 0.5
EYE_COLORS = ((0.8, 0.8, 0.78), (0.06, 0.035, 0.02))  # sclera, iris
CAPSULE_COLOR = (0.3, 0.7, 0.9)
SOLID_COLOR = (0.8, 0.62, 0.5)

_skins: dict[int, SkinMesh | None] = {}  # id(model) -> its human's mesh (None: no human for it); models are cached


def clear_cache() -> None:
    _skins.clear()


def forget_skins() -> None:
    """Drop the built skins and the body data they were fitted from (~30 MB; the scene's meshes stay): a headless
    job calls it before a long bake. A later manikin fits its skin again (~0.3 s)."""
    from ...solver.bodymesh import forget_loaded

    clear_cache()
    forget_loaded()


def human_mesh(model: Model, layout: RigLayout) -> SkinMesh | None:
    """The skinned human of ``model`` (built once per model), or None for a model without one (the snake)."""
    if id(model) not in _skins:
        from ...solver.bodymesh import fit_body  # ~0.3 s on the first manikin of a session, then per new model

        try:
            _skins[id(model)] = skin_mesh(fit_body(model), layout)
        except ModelError:
            _skins[id(model)] = None
    return _skins[id(model)]


def _material(name: str, color: tuple[float, float, float], roughness: float, shaded: bool = False):
    """Our shared material ``name`` (made once): a Principled BSDF of ``color``, also the viewport colour;
    ``shaded``: pictures keep its roughness (``SHADED_KEY``)."""
    material = bpy.data.materials.get(name)
    if material is None:
        material = bpy.data.materials.new(name)
        material[SHADED_KEY] = shaded
        material.diffuse_color = (*color, 1.0)
        material.roughness = roughness
        bsdf = node_tree(material).nodes.get("Principled BSDF")
        if bsdf is not None:
            bsdf.inputs["Base Color"].default_value = (*color, 1.0)
            bsdf.inputs["Roughness"].default_value = roughness
    return material


def _fill(mesh: bpy.types.Mesh, vertices: np.ndarray, corners: np.ndarray, sizes: np.ndarray) -> None:
    """What ``mesh.from_pydata(vertices, [], polygons)`` makes (the same mesh), from arrays: ``corners`` every
    polygon's vertex indices in turn, ``sizes`` each polygon's count (a human has ~20,000: no list per polygon)."""
    sizes = np.asarray(sizes, dtype=np.int32)
    mesh.vertices.add(len(vertices))
    mesh.loops.add(int(sizes.sum()))
    mesh.polygons.add(len(sizes))
    mesh.vertices.foreach_set("co", np.asarray(vertices, dtype=np.float32).ravel())
    mesh.polygons.foreach_set("loop_start", np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int32))
    mesh.polygons.foreach_set("vertices", np.asarray(corners, dtype=np.int32))
    mesh.shade_flat()
    if len(sizes):
        mesh.update(calc_edges=True, calc_edges_loose=False)


def _mesh_object(arm: bpy.types.Object, name: str, vertices: np.ndarray, corners: np.ndarray, sizes: np.ndarray,
                 groups: dict[str, tuple[np.ndarray, np.ndarray]], mode: str) -> bpy.types.Object:  # fmt: skip
    """A mesh object on ``arm`` (polygons as :func:`_fill` takes them): weighted by ``groups`` (bone -> vertex
    indices, weights), deformed by an Armature modifier, in the armature's collection."""
    mesh = bpy.data.meshes.new(name)
    _fill(mesh, vertices, corners, sizes)
    mesh.shade_smooth()
    obj = bpy.data.objects.new(name, mesh)
    obj.parent = arm
    obj.hide_select = True  # clicks go to the bones and empties, not the skin
    obj[DISPLAY_KEY] = mode
    (arm.users_collection[0] if arm.users_collection else bpy.context.scene.collection).objects.link(obj)
    for bone, (index, weight) in groups.items():
        group = obj.vertex_groups.new(name=bone)
        for i, w in zip(index.tolist(), weight.tolist(), strict=True):
            group.add((i,), w, "REPLACE")
    obj.modifiers.new("Armature", "ARMATURE").object = arm
    return obj


def _rigid(arm: bpy.types.Object, layout: RigLayout, body: BodyMesh, name: str, mode: str, color) -> bpy.types.Object:
    """A mesh whose every vertex follows one bone (the solids, the capsules)."""
    groups = {}
    for b, bone in enumerate(layout.bones):
        index = np.flatnonzero(body.vertex_bone == b)
        if len(index):
            groups[bone.name] = (index, np.ones(len(index)))
    corners, sizes = [i for face in body.faces for i in face], [len(face) for face in body.faces]
    obj = _mesh_object(arm, name, body.vertices, corners, sizes, groups, mode)
    obj.data.materials.append(_material(f"manikin.{mode.lower()}", color, 0.6))
    return obj


def _human(arm: bpy.types.Object, skin: SkinMesh, name: str) -> bpy.types.Object:
    obj = _mesh_object(arm, name, skin.vertices, skin.corners, skin.sizes, skin.groups, "HUMAN")
    mesh = obj.data
    mesh.materials.append(_material(SKIN_MATERIAL, SKIN_COLOR, SKIN_ROUGHNESS, shaded=True))
    for material, color in zip(EYE_MATERIALS, EYE_COLORS, strict=True):
        mesh.materials.append(_material(material, color, 0.3, shaded=True))
    mesh.polygons.foreach_set("material_index", skin.materials)
    subdivision = obj.modifiers.new("Subdivision", "SUBSURF")
    subdivision.levels, subdivision.render_levels = 0, 1  # smooth renders; the viewport stays light
    return obj


def bodies(arm: bpy.types.Object) -> dict[str, bpy.types.Object]:
    """The armature's body objects by display mode. A manikin saved before the displays existed has its solids
    untagged as ``<armature>.body``: they are tagged SOLIDS here."""
    for child in arm.children:
        if child.type == "MESH" and DISPLAY_KEY not in child and child.name == arm.name + BODY_SUFFIX:
            child[DISPLAY_KEY] = "SOLIDS"
    return {child[DISPLAY_KEY]: child for child in arm.children if child.get(DISPLAY_KEY) in MODES}


def build(arm: bpy.types.Object, model: Model, layout: RigLayout, mode: str) -> bpy.types.Object | None:
    """Make the body object of ``mode`` (None: HUMAN for a model without a human mesh)."""
    base = arm.name
    if mode == "HUMAN":
        skin = human_mesh(model, layout)
        return None if skin is None else _human(arm, skin, base + BODY_SUFFIX)
    if mode == "CAPSULES":
        return _rigid(arm, layout, capsule_mesh(layout, capsules_of(model)), base + DISPLAY_SUFFIXES[mode], mode,
                      CAPSULE_COLOR)  # fmt: skip
    name = base + (BODY_SUFFIX if "HUMAN" not in bodies(arm) and human_mesh(model, layout) is None else
                   DISPLAY_SUFFIXES[mode])  # fmt: skip
    return _rigid(arm, layout, build_body_mesh(layout), name, mode, SOLID_COLOR)


def show(arm: bpy.types.Object, model: Model, layout: RigLayout, mode: str) -> str:
    """Show the body of ``mode`` (built if missing) and hide the others; the mode shown (SOLIDS where HUMAN was
    asked for a model without a human mesh)."""
    found = bodies(arm)
    if mode not in found:
        made = build(arm, model, layout, mode)
        if made is None:
            return show(arm, model, layout, "SOLIDS")
        found[mode] = made
    for key, obj in found.items():
        obj.hide_viewport = obj.hide_render = key != mode
    return mode
