"""Reach envelopes as objects (the scene side of ``python -m solver envelope``): what Import Reach Envelope does, as
functions. Each mesh of an envelope file becomes a mesh object whose origin is the shoulder the envelope is centred
on, parented to the manikin (its vertices are in the manikin's frame, so the envelope stands where the manikin
stands, turned with it), or placed in the world when there is no manikin. An object an earlier import of the same
file made is replaced. The file is read by :func:`solver.envelope.mesh_files.read_envelope` (numpy only, so it works
in a Blender's own Python).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import bpy
from mathutils import Matrix

from ..scene.schema import ENVELOPE_KEY, FILE_KEY, PRESET_KEY

if TYPE_CHECKING:
    from ...solver.envelope.mesh_files import EnvelopeFile

# viewport colour (RGBA) and display of each envelope: in balance solid and see-through, without balance as a wire
LOOKS = {"balanced": ((0.15, 0.65, 0.35, 0.35), "SOLID"), "kinematic": ((0.6, 0.6, 0.65, 1.0), "WIRE")}
OTHER_LOOK = ((0.8, 0.6, 0.2, 0.35), "SOLID")


def _material(name: str, colour: tuple) -> bpy.types.Material:
    material = bpy.data.materials.get(name) or bpy.data.materials.new(name)
    material.diffuse_color = colour  # the viewport (solid mode) colour
    return material


def _remove_earlier(source: str) -> None:
    """Remove the objects an earlier import of ``source`` made (and their meshes when nothing else uses them)."""
    for old in [ob for ob in bpy.data.objects if ob.get(ENVELOPE_KEY) == source]:
        mesh = old.data
        bpy.data.objects.remove(old, do_unlink=True)
        if isinstance(mesh, bpy.types.Mesh) and mesh.users == 0:
            bpy.data.meshes.remove(mesh)


def add_envelope(
    collection: bpy.types.Collection, envelope: EnvelopeFile, path: str, arm: bpy.types.Object | None
) -> list[bpy.types.Object]:
    """An object per mesh of ``envelope`` (read from ``path``) in ``collection``, origin at the shoulder, parented
    to ``arm`` (None: in the world, the manikin taken at the origin); the objects, named ``<file stem>.<mesh>``."""
    source = str(Path(path).resolve())
    _remove_earlier(source)
    stem = Path(path).stem
    shoulder = envelope.shoulder
    made = []
    for item in envelope.meshes:
        name = f"{stem}.{item.name}"
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata((item.vertices - shoulder).tolist(), [], item.faces.tolist())
        mesh.validate()
        colour, display = LOOKS.get(item.name, OTHER_LOOK)
        mesh.materials.append(_material(f"manikin.envelope.{item.name}", colour))
        ob = bpy.data.objects.new(name, mesh)
        collection.objects.link(ob)
        ob.display_type = display
        ob.color = colour
        ob.show_transparent = colour[3] < 1.0
        ob[ENVELOPE_KEY] = source
        local = Matrix.Translation(tuple(float(v) for v in shoulder))
        if arm is not None:
            ob.parent = arm
            ob.matrix_parent_inverse = Matrix.Identity(4)
            ob.matrix_basis = local
        else:
            ob.matrix_world = local
        made.append(ob)
    return made


def body_name(arm: bpy.types.Object) -> str:
    """The name a manikin's body has in an envelope file: its preset, or its body file's stem."""
    return arm.get(PRESET_KEY) or Path(arm.get(FILE_KEY, "")).stem


def import_envelope(context: bpy.types.Context, path: str, arm: bpy.types.Object | None
                    ) -> tuple[list[bpy.types.Object], str]:  # fmt: skip
    """Read the envelope file ``path`` and add its objects on ``arm`` (None: in the world, in the scene's own
    collection); (the objects, a warning or "" : the envelope is another body's). ManikinError for a bad file,
    before anything changes."""
    from ...solver.envelope.mesh_files import read_envelope

    envelope = read_envelope(path)
    collection = arm.users_collection[0] if arm is not None else context.scene.collection
    made = add_envelope(collection, envelope, path, arm)
    manikin = envelope.info.get("manikin", "")
    if arm is not None and manikin and manikin != body_name(arm):
        return made, f"the envelope is {manikin}'s, placed on {arm.name} ({body_name(arm)})"
    return made, ""
