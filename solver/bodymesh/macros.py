"""MakeHuman's macro modifiers: sex, muscle, weight and height values in [0, 1] -> target weights -> a shaped body.

Each macro value blends the targets named after its levels with piecewise-linear "hat" weights (MakeHuman's
``macro.json`` parts): gender 0 = female, 1 = male; muscle and weight 0 = min, 0.5 = average, 1 = max; height
0 = minheight, 0.5 = no target, 1 = maxheight (likewise proportions, which we leave at 0.5: none). A target that
names several levels gets the *product* of their weights, so the weights of each family sum to 1:

- ``{g}-young`` (sex and age; MakeHuman's default race mix, a third each, baked in by the data preparation):
  w_g;
- ``{g}-young-{m}muscle-{w}weight`` ("universal"): w_g * w_m * w_w;
- ``{g}-young-{m}muscle-{w}weight-{h}height``: w_g * w_m * w_w * w_h.

Age is fixed at 0.5 (25 years, MakeHuman's "young"); only those targets ship. The shaped points are the base
points plus the weighted sum of the targets' deltas (m).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from .data import BodyData

AGE = "young"
LEVELS = ("min", "average", "max")


@dataclass(frozen=True)
class Macros:
    """MakeHuman macro values, each in [0, 1] (0.5 is MakeHuman's default for all but gender)."""

    gender: float = 0.5  # 0 female, 1 male
    muscle: float = 0.5  # 0 min, 0.5 average, 1 max
    weight: float = 0.5  # 0 min, 0.5 average, 1 max
    height: float = 0.5  # 0 min, 0.5 none, 1 max

    def __post_init__(self) -> None:
        for name in ("gender", "muscle", "weight", "height"):
            value = getattr(self, name)
            if not 0.0 <= value <= 1.0:
                raise ModelError(f"body mesh macro {name}: expected a value in [0, 1], got {value}")


def three_levels(value: float) -> dict[str, float]:
    """min / average / max weights of a value in [0, 1]: hats peaking at 0, 0.5 and 1."""
    low, high = max(0.0, 1.0 - 2.0 * value), max(0.0, 2.0 * value - 1.0)
    return {"min": low, "average": 1.0 - low - high, "max": high}


def target_weights(macros: Macros) -> dict[str, float]:
    """Stored target name -> weight (only the non-zero ones)."""
    genders = {"female": 1.0 - macros.gender, "male": macros.gender}
    muscles, weights = three_levels(macros.muscle), three_levels(macros.weight)
    heights = {"min": max(0.0, 1.0 - 2.0 * macros.height), "max": max(0.0, 2.0 * macros.height - 1.0)}
    out: dict[str, float] = {}
    for g, wg in genders.items():
        out[f"{g}-{AGE}"] = wg
        for m in LEVELS:
            for w in LEVELS:
                body = wg * muscles[m] * weights[w]
                out[f"{g}-{AGE}-{m}muscle-{w}weight"] = body
                for h, wh in heights.items():
                    out[f"{g}-{AGE}-{m}muscle-{w}weight-{h}height"] = body * wh
    return {name: w for name, w in out.items() if w > 0.0}


def shape(data: BodyData, macros: Macros) -> np.ndarray:
    """(N + A, 3) m: the base points moved by the macro targets."""
    points = data.points
    for name, w in target_weights(macros).items():
        try:
            index, delta = data.targets[name]
        except KeyError:
            raise ModelError(f"body mesh data: target '{name}' missing") from None
        np.add.at(points, index, w * delta)
    return points
