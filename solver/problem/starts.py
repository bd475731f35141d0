"""Start poses chosen by the task: a crouched start besides the standing one when a reach target is low.

A local solver stays in the basin of its start. From the standing zero pose the comfort step straightens a knee
that has no reason to bend yet, so the solver stoops to a low box even where a squat is the more comfortable pose
it can reach. The rule (no per-task knob): when any reach target that holds a height lies below the standing hip
joint, the pose is solved from the standing start and from :func:`crouched_pose`, and the one that meets its
constraints and is more comfortable is kept (docs/explanation/mocap-validation.md measures it).
"""

from __future__ import annotations

import numpy as np

from .problem import Problem

# The crouch: knees 100 deg, hips 80 deg, ankles 15 deg dorsiflexed, on both sides (a half squat; the solver
# moves on from it). From 110-120 deg knees it lands on the same poses.
CROUCH_DEG = {"knee_{s}_flexion": 100.0, "hip_{s}_flexion": 80.0, "ankle_{s}_dorsiflexion": 15.0}
HIP_JOINT = "hip_r_flexion"


def crouched_pose(model) -> np.ndarray | None:
    """The zero pose with the legs bent as :data:`CROUCH_DEG` (within limits), None when the model has no such legs."""
    theta = model.zero_pose().copy()
    names = model.joint_names
    for side in ("r", "l"):
        for template, degrees in CROUCH_DEG.items():
            name = template.format(s=side)
            if name not in names:
                return None
            i = names.index(name)
            theta[i] = np.clip(np.radians(degrees), model.lower[i], model.upper[i])
    return theta


def low_reach(problem: Problem) -> bool:
    """Whether a reach target (not a support) that holds a height (locks z) lies below the standing hip joint (m,
    world z; the zero pose stands on z = 0)."""
    model = problem.model
    if HIP_JOINT not in model.joint_names:
        return False
    zero = model.forward(model.zero_pose())
    hip = zero.position[model.joint_names.index(HIP_JOINT)][2]
    for target in problem.spec.targets:
        if target.support or not target.enabled or target.operator is not None or "z" not in target.lock:
            continue
        if float(target.position[2]) < hip:  # the zero pose stands on z = 0
            return True
    return False


def start_poses(problem: Problem) -> list[np.ndarray]:
    """The start poses of the rule above: the zero pose, and the crouched pose when a reach target is low."""
    starts = [problem.model.zero_pose()]
    crouch = crouched_pose(problem.model) if low_reach(problem) else None
    return starts + ([crouch] if crouch is not None else [])
