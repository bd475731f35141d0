"""Obstacle kinds: one module per kind, each one frozen shape class with the interface of
:class:`~solver.collision.kinds.base.Obstacle`, and the registry of them by the name a scenario's ``kind`` gives.

A new kind is a new module here and one line below (``register``); the scenario files, the clearance rows, the
carried box, the swept checks between frames and Blender's obstacles then know it (docs/develop/recipes_registries.md).
"""

from __future__ import annotations

from .base import Obstacle, ShapeGroup, obstacle_distance
from .box import Box
from .capsule import Capsule
from .cylinder import Cylinder
from .mesh import Mesh, read_mesh
from .plane import HalfSpace
from .sphere import Sphere

KINDS: dict[str, type[Obstacle]] = {}  # by the scenario's ``kind = "..."``, in the order they are listed to a user


def register(kind: type[Obstacle]) -> type[Obstacle]:
    """Add an obstacle kind to :data:`KINDS` under its ``kind`` name (one name, one kind)."""
    if kind.kind in KINDS and KINDS[kind.kind] is not kind:
        raise ValueError(f"obstacle kind {kind.kind!r} is registered already")
    KINDS[kind.kind] = kind
    return kind


register(Box)
register(Sphere)
register(Capsule)
register(HalfSpace)
register(Mesh)
register(Cylinder)


def kind_of(name: str) -> type[Obstacle]:
    """The registered kind called ``name`` (KeyError naming the known ones if there is none)."""
    try:
        return KINDS[name]
    except KeyError:
        raise KeyError(f"unknown obstacle kind {name!r}; known: {', '.join(KINDS)}") from None


__all__ = ["KINDS", "Box", "Capsule", "Cylinder", "HalfSpace", "Mesh", "Obstacle", "ShapeGroup", "Sphere", "kind_of",
           "obstacle_distance", "read_mesh", "register"]
