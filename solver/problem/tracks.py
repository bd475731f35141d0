"""Targets keyed over frames: a track's keys and the target list at any frame.

A keyed target holds its first key before it and its last key after it; in between, positions are
interpolated linearly and rotations by slerp.
"""

from __future__ import annotations

import bisect
import functools
from dataclasses import dataclass

import numpy as np

from ..body.spatial import Arc, matrix_to_quat, quat_to_matrix
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
        position = (1.0 - t) * a.position + t * b.position
        if a.rotation is None or b.rotation is None:
            return position, a.rotation if b.rotation is None else b.rotation
        held = self._held[i]
        return position, held if held is not None else quat_to_matrix(self._arcs[i].at(t))

    @functools.cached_property
    def _frames(self) -> list[int]:
        return [k.frame for k in self.keys]

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
