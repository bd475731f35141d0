"""What a user chooses, as plain frozen values (no NumPy): the axis names of a lock, the solver's options and the
per-frame limits of a motion. Light to import, so the Blender layer can build its settings without the solver."""

from __future__ import annotations

from dataclasses import dataclass

AXES = ("x", "y", "z", "rx", "ry", "rz")  # the error components of a frame target: position, then rotation vector
MAX_FRAME = 1048574  # the largest frame number (Blender's): a scenario's frames become a Blender scene's
MAX_FRAMES = 100000  # frames in one motion
MIN_WEIGHT, MAX_WEIGHT = 1e-6, 100.0  # relative weights of targets, loops and comfort terms (beyond: ill-conditioned)


@dataclass(frozen=True)
class SolverOptions:
    """What a user chooses per solve: the budget, whether comfort is optimised, its tolerance, restarts.

    How the method itself steps and stops is fixed in :class:`solver.iteration.Tuning`.
    """

    max_iterations: int = 100
    optimize_comfort: bool = True
    comfort_tolerance: float = 3e-3  # stop when the predicted comfort gain is below this fraction of max(|h|, 1)
    restarts: int = 1  # solves again from :func:`solver.iteration.restart_pose` when the constraints are not met


DEFAULT_OPTIONS = SolverOptions()


@dataclass(frozen=True)
class MotionLimits:
    """Largest change between consecutive frames."""

    max_joint_change: float = 0.35  # rad per frame
    max_root_shift: float = 0.10  # m per frame


DEFAULT_LIMITS = MotionLimits()
