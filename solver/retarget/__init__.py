"""Baked Manikin motions onto other skeletons (Mixamo, Rigify, game-engine, MPFB rigs or any humanoid). NumPy only.

    skel = skeleton(names, parents, rest, lengths)       # an armature at rest (world frames, m)
    bone_map = auto_map(ours, theirs)                    # our bone -> their bone, from name patterns
    check_map(bone_map, ours.names, theirs.names)        # ModelError naming what is missing
    plan = retarget_plan(ours, theirs, bone_map, R)      # leg-length ratio, origins, bones to key
    poses, misses = pose_frame(plan, our_world_poses, pinned={"foot_l", "foot_r"})
    basis = basis_matrices(theirs, poses, scale)         # local transforms to key

Modules: :mod:`.skeleton` (arrays, rigid frames), :mod:`.transfer` (rest alignment, hips, IK pins),
:mod:`.two_bone` (the IK), :mod:`.names` (auto-fill from bone names), :mod:`.bone_map` (shipped TOML maps, checks),
:mod:`.shipped` (the MPFB rigs placed on a fitted body). How: ``docs/RETARGET.md``.
"""
