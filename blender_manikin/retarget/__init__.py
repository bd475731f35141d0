"""Retargeting a baked manikin motion onto other armatures (bpy): ``armatures`` (reading any armature, building the
shipped MPFB rigs), ``motion`` (the retarget run and its keys), ``properties`` (the bone map stored on the target),
``operators`` and ``panel`` (the sidebar), ``headless`` (the batch script's ``--retarget``), ``rig_checks`` (generated
Rigify rigs refused, bones driven by constraints named) and ``progress``. The math is
``solver.retarget``."""
