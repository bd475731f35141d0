"""Baking a motion (bpy): ``bake`` (the frame-by-frame solve and the bulk keys), ``operators`` (Bake Motion, modal
with progress and Esc), ``panel`` (the Motion subpanel), ``exports`` (FBX, BVH, glTF through Blender's exporters)
and the headless pipeline behind ``batch.py`` and the demo: ``job`` (a scene in, a bake, files out), ``report``
(the per-frame JSON report, no bpy), ``picture`` (key poses rendered side by side) and ``quiet`` (Blender's own
console output kept out, no bpy). This ``__init__`` imports nothing."""
