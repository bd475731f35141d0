"""The MPFB 2 rigs shipped in ``presets/body_mesh/mpfb2_rigs.json``, placed on a manikin's fitted body, with their
bone maps (``presets/bone_maps/<rig>.toml``). NumPy only.

Each rig's bones sit where :meth:`solver.bodymesh.FittedBody.rig` puts them (the MPFB joints moved with the fitted
skin, so in our zero pose: arms hanging, palms on the thighs). MPFB's bone rolls are for its own A-pose; the roll
is carried over by the smallest rotation from MPFB's rest direction of the bone to the fitted one, so each bone's
x axis stays where MPFB has it relative to the body (the Blender layer does that with Blender's roll convention).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bodymesh import FittedBody
from ..errors import ModelError
from .bone_map import SHIPPED_RIGS, load_map, shipped_path

RIG_TABLES = {name: table for name, (table, _) in SHIPPED_RIGS.items()}  # our name -> table in mpfb2_rigs.json
MIN_BONE = 0.01  # m: a zero-length bone gets this length (along MPFB's direction, else up): Blender drops them


@dataclass(frozen=True)
class RigBone:
    """One bone of a shipped rig on a fitted body (m, the manikin's armature space)."""

    name: str
    parent: str | None
    head: np.ndarray
    tail: np.ndarray
    roll: float  # rad, MPFB's, for ``rest_head`` -> ``rest_tail``
    rest_head: np.ndarray  # MPFB's own rest position (the unshaped base mesh, A-pose)
    rest_tail: np.ndarray
    connect: bool
    rigify_type: str  # "" unless the rig is Rigify's metarig


def rig_bones(body: FittedBody, rig: str) -> list[RigBone]:
    """The bones of shipped rig ``rig`` (a key of :data:`RIG_TABLES`) on ``body``, parents before children."""
    if rig not in RIG_TABLES:
        raise ModelError(f"no shipped rig '{rig}' (known: {', '.join(RIG_TABLES)})")
    table = body.data.rigs[RIG_TABLES[rig]]["bones"]
    placed = body.rig(RIG_TABLES[rig])
    out: list[RigBone] = []
    done: set[str] = set()

    def add(name: str) -> None:
        if name in done:
            return
        b = table[name]
        if b["parent"] is not None:
            add(b["parent"])
        head, tail = placed[name]
        rest_head, rest_tail = np.asarray(b["rest_head"], float), np.asarray(b["rest_tail"], float)
        if np.linalg.norm(tail - head) < 1e-6:
            direction = rest_tail - rest_head if np.linalg.norm(rest_tail - rest_head) > 1e-6 else np.eye(3)[2]
            tail = head + MIN_BONE * direction / np.linalg.norm(direction)
            rest_tail = rest_head + MIN_BONE * direction / np.linalg.norm(direction)
        out.append(RigBone(name, b["parent"], head, tail, float(b["roll"]), rest_head, rest_tail,
                           bool(b["connect"]), str(b.get("rigify_type", ""))))  # fmt: skip
        done.add(name)

    for name in table:
        add(name)
    return out


def rig_map(rig: str) -> dict[str, str]:
    """The shipped bone map of rig ``rig``: our bone -> its bone."""
    if rig not in RIG_TABLES:
        raise ModelError(f"no shipped rig '{rig}' (known: {', '.join(RIG_TABLES)})")
    return load_map(shipped_path(rig))[1]
