"""Operations from the sidebar (issue 36): meshes marked as objects with grasp empties, a list of operations over
them on the scene, and Generate Motion: the scene as a scenario with ``[[objects]]`` and ``[[operations]]``, planned
and solved by ``python -m solver operate`` in the background, the result keyed onto the manikin and the objects."""
