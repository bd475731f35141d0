"""Operations over objects (``[[objects]]``, ``[[operations]]`` in a scenario) turned into a solved motion.

One module per job: :mod:`.objects` (objects, their grasps, grasps proposed from geometry), :mod:`.schema` (the
scenario tables read), :mod:`.timing` (MTM-1 durations, minimum-jerk profiles), :mod:`.ways` (the way between two
points: straight until the path planner lands), :mod:`.stance` (where the feet go: the given stance until
``find_stance`` lands), :mod:`.timeline` (operations -> timed segments), :mod:`.frames` (a segment's targets and
problem at a frame), :mod:`.generate` (every frame solved with the motion solver). Units: m, s, kg, rad.
"""
