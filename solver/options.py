"""What a user chooses, as plain frozen values (no NumPy): the axis names of a lock, the solver's options and the
per-frame limits of a motion. Light to import, so the Blender layer can build its settings without the solver."""

from __future__ import annotations

from dataclasses import dataclass

AXES = ("x", "y", "z", "rx", "ry", "rz")  # the error components of a frame target: position, then rotation vector


@dataclass(frozen=True)
class SolverOptions:
    """Iteration limits and step controls; steps are in scaled variables (1 = half a joint's range)."""

    max_iterations: int = 100
    optimize_comfort: bool = True
    max_step: float = 1.0  # trust region: largest 2-norm of a task step in scaled variables
    max_comfort_step: float = 0.5  # same for the comfort part of a step
    comfort_tolerance: float = 3e-3  # stop when the predicted comfort gain is below this fraction of max(|h|, 1)
    max_damping: float = 1e-3  # Tikhonov damping of the task step, as a fraction of the largest singular value
    clamping_rounds: int = 10
    restarts: int = 1  # solves again from :func:`solver.iteration.restart_pose` when the constraints are not met


DEFAULT_OPTIONS = SolverOptions()


@dataclass(frozen=True)
class MotionLimits:
    """Largest change between consecutive frames."""

    max_joint_change: float = 0.35  # rad per frame
    max_root_shift: float = 0.10  # m per frame


DEFAULT_LIMITS = MotionLimits()
