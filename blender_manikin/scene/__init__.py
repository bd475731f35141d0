"""Reading and writing the Blender scene (bpy): the manikin's armature, body and empties, poses, keyframes, bakes
and exports. ``schema`` names every custom property and object; ``compat`` holds every Blender-version difference.
No operators or panels here (those are ``ui/``); this package's ``__init__`` imports nothing.
"""
