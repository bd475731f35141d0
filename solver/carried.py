"""A box carried between two TCPs (``[carried]`` in a scenario): where it is, from where the two TCPs are.

The box is no obstacle: it moves with the hands, so the solver does not see it; pictures and the .blend show it,
and tests check that the body stays out of it. Its centre is the midpoint of the two TCPs, its x axis runs from
the first TCP to the second, its z axis is as near world up as that allows. ``size`` (m) is along x (between the
hands), y (depth) and z (height). Units: m.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .collision import Box


@dataclass(frozen=True)
class Carried:
    """A box of ``size`` (m: across the hands, depth, height) held between the TCPs ``tcps`` (first, second)."""

    size: np.ndarray
    tcps: tuple[str, str]
    name: str = "carried box"


def carried_frame(first: np.ndarray, second: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(centre (3,) m, rotation (3, 3): columns x, y, z) of a box held between the points ``first`` and
    ``second`` (m, world). Upright: x from first to second, z world up made square to x; a vertical x (the hands
    one above the other) takes world y as its reference instead."""
    first, second = np.asarray(first, dtype=float), np.asarray(second, dtype=float)
    x = second - first
    x = x / max(float(np.linalg.norm(x)), 1e-12)
    up = np.array([0.0, 0.0, 1.0]) if abs(x[2]) < 0.99 else np.array([0.0, 1.0, 0.0])
    z = up - x * float(up @ x)
    z /= np.linalg.norm(z)
    return (first + second) / 2.0, np.column_stack([x, np.cross(z, x), z])


def carried_box(carried: Carried, first: np.ndarray, second: np.ndarray) -> Box:
    """The carried box as a :class:`~solver.collision.Box` when its TCPs are at ``first`` and ``second`` (m)."""
    centre, rotation = carried_frame(first, second)
    return Box(centre, carried.size, rotation, name=carried.name)
