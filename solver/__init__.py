"""Manikin pose prediction: a balanced, comfort-maximising unified IK solver in NumPy/SciPy (no bpy)."""
