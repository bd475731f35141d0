"""How a solver model maps onto Blender data, computed without bpy (NumPy only, testable anywhere): the bones, rest
frames and pose channels of the armature (``bones``) and the body mesh riding on them (``body_mesh``)."""
