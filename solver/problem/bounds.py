"""Box bounds of the solver's variables (joint ranges, pushing-only contacts, a motion's per-frame change) as one
immutable value, with the scaled unit of each variable."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..body.model import Model


def joint_scale(model: Model) -> np.ndarray:
    """Scaled-variable unit per joint: half its range, within [0.02, 1] (rad or m).

    A minimum-norm step in scaled variables then shares motion in proportion to each joint's range, so the
    72 vertebrae (a few degrees each) do not saturate before the hips and shoulders move; it is also the
    diagonal Newton scaling of the comfort's tan^2 range term.
    """
    half = 0.5 * (model.upper - model.lower)
    return np.where(np.isfinite(half), np.clip(half, 0.02, 1.0), 1.0)


@dataclass(frozen=True, eq=False)
class Bounds:
    """lower <= v <= upper per variable (rad, m or N; +-inf when free), ``scale`` its scaled unit (half a joint's
    range, body weight for a force), ``is_joint`` False for contact edge weights. Arrays are read-only copies."""

    lower: np.ndarray
    upper: np.ndarray
    scale: np.ndarray
    is_joint: np.ndarray

    def __post_init__(self) -> None:
        for name in ("lower", "upper", "scale", "is_joint"):
            value = np.array(getattr(self, name), dtype=bool if name == "is_joint" else float)
            value.flags.writeable = False
            object.__setattr__(self, name, value)

    @classmethod
    def of_model(cls, model: Model, n_forces: int, body_weight: float) -> Bounds:
        """Over x = [joints, contact edge weights]: the joint ranges, and weights >= 0 (a floor only pushes)."""
        return cls(
            np.concatenate([model.lower, np.zeros(n_forces)]),
            np.concatenate([model.upper, np.full(n_forces, np.inf)]),
            np.concatenate([joint_scale(model), np.full(n_forces, body_weight)]),
            np.arange(model.n + n_forces) < model.n,
        )

    def __len__(self) -> int:
        return len(self.lower)

    def clip(self, v: np.ndarray) -> np.ndarray:
        """``v`` moved into the box."""
        return np.clip(v, self.lower, self.upper)

    def room(self, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """How far each variable may move from ``v`` down and up, in scaled units (<= 0 and >= 0 inside)."""
        return (self.lower - v) / self.scale, (self.upper - v) / self.scale

    def around(self, center: np.ndarray, step: np.ndarray) -> Bounds:
        """These bounds narrowed to within ``step`` of ``center`` (a motion's per-frame change)."""
        lower = np.maximum(self.lower, center - step)
        upper = np.minimum(self.upper, center + step)
        # Bounds(lower, upper, self.scale, self.is_joint) without its four copies: lower and upper are new float64
        # arrays of no one else, scale and is_joint read-only copies already (a motion narrows its bounds every frame)
        lower.flags.writeable = upper.flags.writeable = False
        out = object.__new__(Bounds)
        for name, value in (("lower", lower), ("upper", upper), ("scale", self.scale), ("is_joint", self.is_joint)):
            object.__setattr__(out, name, value)
        return out

    def held(self, v: np.ndarray, wider: Bounds) -> np.ndarray:
        """Variables at a bound of these bounds that ``wider`` does not have (held by the narrowing)."""
        return (np.isclose(v, self.lower) & (self.lower > wider.lower)) | (
            np.isclose(v, self.upper) & (self.upper < wider.upper)
        )
