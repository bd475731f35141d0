"""Balanced reach envelopes: how far a hand reaches from its shoulder in every direction with the feet planted (or
allowed to step), in static balance (with a hand-held load) and without it, as meshes (OBJ, GLB), a CSV and a
picture.

::

    sphere = direction_sphere(3)                      # 92 directions (geodesic), or a hemisphere of them
    envelope = sweep_envelope(load_preset("male_50"), sphere, "right", load_kg=10.0)   # -> Envelope (radii, m)
    stats = comparison(envelope)                      # how much balance takes off, per sector
    row = reach_row("male_50", (0, -1, -1), load_kg=10.0)   # one plain run -> dict (a study runner's unit)
    envelope, stats = compute_envelope(model, "right", EnvelopeSettings(feet="step"))   # what the CLI and a study run
    meshes = read_envelope("out/male_50_right.glb")   # numpy only: what the Blender import uses

``python -m solver envelope ...`` writes them (:mod:`.cli`). Names load their module on first use (PEP 562), so
importing this package (as the Blender layer does) loads neither scipy nor matplotlib.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..lazy import lazy_attributes

_HOMES = {
    "Envelope": "sweep",
    "EnvelopeFile": "mesh_files",
    "EnvelopeMesh": "mesh_files",
    "EnvelopeSettings": "job",
    "comparison": "analysis",
    "compute_envelope": "job",
    "direction_sphere": "directions",
    "glb_bytes": "mesh_files",
    "obj_text": "mesh_files",
    "reach_row": "run",
    "read_envelope": "mesh_files",
    "search_ray": "reach",
    "sweep_envelope": "sweep",
}
__all__ = [
    "Envelope",
    "EnvelopeFile",
    "EnvelopeMesh",
    "EnvelopeSettings",
    "comparison",
    "compute_envelope",
    "direction_sphere",
    "glb_bytes",
    "obj_text",
    "reach_row",
    "read_envelope",
    "search_ray",
    "sweep_envelope",
]

if TYPE_CHECKING:
    from .analysis import comparison
    from .directions import direction_sphere
    from .job import EnvelopeSettings, compute_envelope
    from .mesh_files import EnvelopeFile, EnvelopeMesh, glb_bytes, obj_text, read_envelope
    from .reach import search_ray
    from .run import reach_row
    from .sweep import Envelope, sweep_envelope


__getattr__ = lazy_attributes(__name__, _HOMES, globals())
