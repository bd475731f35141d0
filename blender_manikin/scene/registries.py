"""The solver's registries as Blender shows them (no bpy): the obstacle shape menu from the obstacle kinds
(:data:`solver.collision.kinds.KINDS`) and the comfort weights from the standard comfort terms
(:data:`solver.comfort.standard.STANDARD_TERMS`).

``pose/properties.py`` builds its settings from these when the add-on registers, so a kind or a term registered
before then is in the shape menu, the sidebar, the scene's problem and scenario import without a Blender edit. The
registries are imported inside the functions: importing this module costs nothing; calling them loads the solver's
collision and comfort modules (NumPy, no scipy).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

if TYPE_CHECKING:
    from ...solver.collision.kinds import Obstacle
    from ...solver.comfort.standard import ComfortWeights

MESH = "MESH"  # the menu's first item and its default: the object's own triangles


def shape_of(kind: str) -> str:
    """The shape menu's identifier of an obstacle kind: its name in upper case ("box" -> "BOX"), as saved files
    hold it."""
    return kind.upper()


def obstacle_kind(shape: str) -> type[Obstacle]:
    """The registered obstacle kind a shape menu identifier names (KeyError naming the known ones if none)."""
    from ...solver.collision.kinds import kind_of

    return kind_of(shape.lower())


def shape_items() -> list[tuple[str, str, str]]:
    """The shape menu's items (identifier, title, description): the mesh first, then every other registered kind in
    the registry's order. A saved file holds an item's position, so a kind registered later (at the registry's end)
    leaves the earlier items' values as they were."""
    from ...solver.collision.kinds import KINDS

    mesh = obstacle_kind(MESH)
    kinds = [mesh, *(kind for kind in KINDS.values() if kind is not mesh)]
    return [(shape_of(kind.kind), kind.kind.replace("_", " ").title(), kind.description) for kind in kinds]


class ComfortSetting(NamedTuple):
    """A standard comfort term's weight as a setting of the manikin: ``prop`` (``comfort_<name>``) on its settings,
    ``term`` (the registry's name), ``title`` and ``description`` for the sidebar, ``default`` (dimensionless)."""

    prop: str
    term: str
    title: str
    default: float
    description: str


def comfort_settings() -> list[ComfortSetting]:
    """One setting per registered standard comfort term, in the registry's order."""
    from ...solver.comfort.standard import STANDARD_TERMS

    return [ComfortSetting(f"comfort_{name}", name, name.replace("_", " ").title(), float(term.weight),
                           f"Weight: {getattr(term.factory, 'description', '') or name}")
            for name, term in STANDARD_TERMS.items()]  # fmt: skip


def comfort_weights(settings: object, terms: list[ComfortSetting] | None = None) -> ComfortWeights:
    """The comfort weights a manikin's settings hold (a term registered after the add-on has no setting: its
    default). ``terms``: :func:`comfort_settings` (default: made now)."""
    from ...solver.comfort.standard import ComfortWeights

    # a setting is single precision: 0.01 typed is 0.00999999978; its shortest decimal is what was meant
    return ComfortWeights(**{s.term: float(f"{getattr(settings, s.prop, s.default):.7g}")
                             for s in (comfort_settings() if terms is None else terms)})  # fmt: skip


def set_comfort_weights(settings: object, weights: ComfortWeights) -> None:
    """Put ``weights`` (by term name) into a manikin's settings (the terms it has a setting for)."""
    for s in comfort_settings():
        if hasattr(settings, s.prop) and s.term in weights:
            setattr(settings, s.prop, weights[s.term])
