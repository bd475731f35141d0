"""The bpy adapters every feature shares: reading and writing the manikin in a Blender scene. ``schema`` names every
custom property and object, ``compat`` holds every Blender-version difference; ``armature`` (the rig, its model and
pose), ``display`` and ``twist`` (the body on it), ``targets`` (the empties a user moves), ``problem_io`` (the
scene <-> a solver Problem and Result), ``keyframes``, ``carried_object``, ``obstacles`` and ``obstacle_objects``
(scene meshes <-> obstacle shapes), ``supports`` (what the feet may do and did), ``lifecycle`` (delete and duplicate a
manikin), ``background`` (the solver in a subprocess) and ``watch`` (a background job watched by a timer), ``help``
(the panels' documentation links). No operators or panels here (those are in the feature folders); this package's
``__init__`` imports nothing.
"""
