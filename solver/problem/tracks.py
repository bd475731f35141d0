"""Targets keyed over frames: a track's keys and the target list at any frame; two target lists blended.

A keyed target holds its first key before it and its last key after it; in between, positions are
interpolated linearly and rotations by slerp.
"""

from __future__ import annotations

import bisect
import functools
from dataclasses import dataclass, replace

import numpy as np

from ..body.spatial import Arc, matrix_to_quat, quat_to_matrix, slerp
from .specs import Target


@dataclass(frozen=True)
class Key:
    """A target pose at one frame: position (m) and optional rotation (3x3)."""

    frame: int
    position: np.ndarray
    rotation: np.ndarray | None = None


@dataclass(frozen=True)
class Track:
    """The keys of the target at index ``target`` in the scenario's target list, sorted by frame."""

    target: int
    keys: tuple[Key, ...]

    def pose_at(self, frame: float) -> tuple[np.ndarray, np.ndarray | None]:
        """Interpolated (position, rotation) at ``frame``."""
        keys = self.keys
        if frame <= keys[0].frame:
            return keys[0].position, keys[0].rotation
        if frame >= keys[-1].frame:
            return keys[-1].position, keys[-1].rotation
        i = bisect.bisect_right(self._frames, frame) - 1
        a, b = keys[i], keys[i + 1]
        t = (frame - a.frame) / (b.frame - a.frame)
        ends = self._floats
        if ends is not None and type(t) is float:  # the blend in Python floats: NumPy's bits, without its calls
            (x0, y0, z0), (x1, y1, z1), s = ends[i], ends[i + 1], 1.0 - t
            position = np.array([s * x0 + t * x1, s * y0 + t * y1, s * z0 + t * z1])
        else:
            position = (1.0 - t) * a.position + t * b.position
        if a.rotation is None or b.rotation is None:
            return position, a.rotation if b.rotation is None else b.rotation
        held = self._held[i]
        return position, held if held is not None else quat_to_matrix(self._arcs[i].at(t))

    @functools.cached_property
    def _frames(self) -> list[int]:
        return [k.frame for k in self.keys]

    @functools.cached_property
    def _floats(self) -> list[list[float]] | None:
        """Each key's position (m) as three Python floats, or None unless every one is a float64 3-vector (a long
        motion blends two of them every frame)."""
        if all(type(k.position) is np.ndarray and k.position.dtype == np.float64 and k.position.shape == (3,)
               for k in self.keys):  # fmt: skip
            return [k.position.tolist() for k in self.keys]
        return None

    @functools.cached_property
    def _arcs(self) -> list[Arc | None]:
        """The slerp arc from each key's rotation to the next's (None where either has none), built once for every
        frame between them."""
        quats = [None if k.rotation is None else matrix_to_quat(k.rotation) for k in self.keys]
        return [None if a is None or b is None else Arc(a, b) for a, b in zip(quats[:-1], quats[1:], strict=True)]

    @functools.cached_property
    def _held(self) -> list[np.ndarray | None]:
        """Per pair of keys, the rotation between them when both keys hold the same one (the slerp the same at every
        t, to the bit: :attr:`Arc.still`), else None."""
        return [quat_to_matrix(arc.at(0.5)) if arc is not None and arc.still else None for arc in self._arcs]


def targets_at(targets: list[Target], tracks: list[Track], frame: float) -> list[Target]:
    """The target list with every keyed target moved to its pose at ``frame``."""
    out = list(targets)
    for track in tracks:
        position, rotation = track.pose_at(frame)
        out[track.target] = out[track.target].at(position, rotation)
    return out


def blend_targets(a: list[Target], b: list[Target], s: float) -> list[Target] | None:
    """Targets ``s`` of the way from ``a`` to ``b`` (positions linear, rotations by slerp), or None when the two
    lists do not hold the same TCPs in the same order."""
    if [t.tcp for t in a] != [t.tcp for t in b]:
        return None
    out = []
    for ta, tb in zip(a, b, strict=True):
        position = (1.0 - s) * np.asarray(ta.position, dtype=float) + s * np.asarray(tb.position, dtype=float)
        rotation = tb.rotation
        if ta.rotation is not None and tb.rotation is not None:
            rotation = quat_to_matrix(slerp(matrix_to_quat(ta.rotation), matrix_to_quat(tb.rotation), s))
        out.append(replace(tb, position=position, rotation=rotation))
    return out
