"""Populations and manikin families: who a design must fit, as bodies the solver can pose.

::

    pop = population("female")                       # ANSUR II: stature (m), mass (kg), extra measurements (m)
    members = make_family(("male", "female"), coverage=0.95, points=8, samples=100, seed=1)
    write_family(members, "out/family", info)        # one body TOML per member + family.toml
    family = read_family("out/family")               # -> Family: members and their body files

``python -m solver family ...`` does the same from the command line (:mod:`.cli`). Names load their module on
first use (PEP 562), so building the command line's parser costs nothing.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..lazy import lazy_attributes

_HOMES = {
    "Family": "family_files",
    "INDEX": "family_files",
    "Member": "family",
    "Population": "model",
    "boundary_points": "family",
    "coverage_radius": "model",
    "make_family": "family",
    "population": "model",
    "read_family": "family_files",
    "write_family": "family_files",
}
__all__ = [
    "INDEX",
    "Family",
    "Member",
    "Population",
    "boundary_points",
    "coverage_radius",
    "make_family",
    "population",
    "read_family",
    "write_family",
]

if TYPE_CHECKING:
    from .family import Member, boundary_points, make_family
    from .family_files import INDEX, Family, read_family, write_family
    from .model import Population, coverage_radius, population


__getattr__ = lazy_attributes(__name__, _HOMES, globals())
