"""A skinned human body for a manikin, from the CC0 MakeHuman / MPFB 2 data in ``presets/body_mesh``. NumPy only
(a real Blender runs it)::

    body = solver.bodymesh.fit_body(solver.load_preset("male_50"))   # -> FittedBody, about 0.3 s
    body.vertices, body.faces            # (N, 3) m in the zero pose (the armature's rest pose), (F, 4) quads
    body.bone_names, body.weights        # our armature's bones and (N, B) skin weights, rows summing to 1
    body.fit_error                       # landmark -> m: the MPFB joints' distance from ours after the fit
    body.eye_centres, body.eye_radius    # where eyeballs go (the mesh has sockets, no eyes)
    body.rig("mixamo")                   # a shipped rig's bones (head, tail) placed on this body
    solver.bodymesh.forget_loaded()      # drop the data read for fits (~30 MB), e.g. before a long bake

Modules: :mod:`.data` (the shipped files), :mod:`.macros` (MakeHuman's macro blending), :mod:`.landmarks` (the
joint correspondence), :mod:`.fit` (segment affines, skinning), :mod:`.transfer` (weights onto our bones),
:mod:`.measure` (stature, volume, smoothing, inside tests), :mod:`.body` (all of it for one model). How and how
well it fits: ``docs/BODY_MESH.md``.
"""

from .body import FittedBody, calibrate, fit_body, fit_points, forget_loaded
from .data import BodyData, load_body_data, rig_rest
from .macros import Macros, shape, target_weights

__all__ = [
    "BodyData",
    "FittedBody",
    "Macros",
    "calibrate",
    "fit_body",
    "fit_points",
    "forget_loaded",
    "load_body_data",
    "rig_rest",
    "shape",
    "target_weights",
]
