"""Baked Manikin motions onto other skeletons (Mixamo, Rigify, game-engine, MPFB rigs or any humanoid). NumPy only::

    from solver.retarget.skeleton import skeleton            # an armature at rest: world frames (m), parents
    from solver.retarget.names import auto_map               # our bone -> their bone, from their names
    from solver.retarget.bone_map import check_map, load_map  # the checks, the TOML maps in presets/bone_maps
    from solver.retarget.transfer import plan, pose_frame, basis_matrices

    the_plan = plan(ours, theirs, bone_map, our_world_rotation)    # leg-length ratio, origins, rest alignment
    poses, misses = pose_frame(the_plan, our_world_poses, pinned=("foot_l", "foot_r"))
    basis = basis_matrices(theirs, poses, object_scale)              # the local transforms to key

Modules: :mod:`.skeleton` (arrays, rigid frames), :mod:`.transfer` (rest alignment, hips, IK pins),
:mod:`.two_bone` (the IK), :mod:`.names` (auto-fill from bone names), :mod:`.bone_map` (maps, checks, the shipped
rigs' names; light: the add-on imports it when it enables), :mod:`.shipped` (the MPFB rigs placed on a fitted
body). This package imports nothing itself. How, and how well: ``docs/RETARGET.md``.
"""
