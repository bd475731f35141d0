"""Posing a manikin (bpy): ``properties`` (the settings on a manikin, its target, loop and load empties and
obstacle meshes), ``operators`` (add a manikin, targets, loops, loads; solve; reset), ``panels`` (the sidebar tab,
its pose subpanels, Add > Manikin), ``live`` (re-solve while targets move), ``overlay`` (viewport drawing) and
``solve`` (Solve Pose and Reset Pose as functions, for scripts). This ``__init__`` imports nothing."""
