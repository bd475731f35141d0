"""An armature's bones at rest as plain arrays, and the small rotation geometry the retarget needs. NumPy only.

A bone frame is a rigid 4x4 matrix in world space (m): its columns are the bone's x, y (along the bone, head to
tail) and z axes and its head. Blender's ``Bone.matrix_local`` composed with the armature object's world matrix
gives it (the object's uniform scale moves the positions only: :func:`rigid_world`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ModelError

_TINY = 1e-12


@dataclass(frozen=True, eq=False)
class Skeleton:
    """Bones at rest in world space, parents before children."""

    names: tuple[str, ...]
    parents: np.ndarray  # (B,) int, -1 for a root bone
    rest: np.ndarray  # (B, 4, 4) rigid frames (m)
    lengths: np.ndarray  # (B,) m

    @property
    def heads(self) -> np.ndarray:
        return self.rest[:, :3, 3]

    @property
    def tails(self) -> np.ndarray:
        return self.heads + self.rest[:, :3, 1] * self.lengths[:, None]

    def index(self, name: str) -> int:
        try:
            return self.names.index(name)
        except ValueError:
            raise ModelError(f"no bone '{name}' in the armature") from None

    def ancestors(self, b: int) -> list[int]:
        """Bone indices from ``b``'s parent up to its root."""
        out = []
        while self.parents[b] >= 0:
            b = int(self.parents[b])
            out.append(b)
        return out

    def depth(self, b: int) -> int:
        return len(self.ancestors(b))


def skeleton(names: list[str], parents: list[str | None], rest: np.ndarray, lengths: np.ndarray) -> Skeleton:
    """A Skeleton from bones in any order (``parents`` by name, None for a root), sorted parents first."""
    position = {n: i for i, n in enumerate(names)}
    order: list[int] = []
    placed: set[int] = set()

    def place(i: int, seen: tuple[int, ...] = ()) -> None:
        if i in placed:
            return
        if i in seen:
            raise ModelError(f"bone '{names[i]}' is its own ancestor")
        p = parents[i]
        if p is not None:
            if p not in position:
                raise ModelError(f"bone '{names[i]}': parent '{p}' is not in the armature")
            place(position[p], (*seen, i))
        placed.add(i)
        order.append(i)

    for i in range(len(names)):
        place(i)
    new = {old: k for k, old in enumerate(order)}
    return Skeleton(
        names=tuple(names[i] for i in order),
        parents=np.array([new[position[parents[i]]] if parents[i] is not None else -1 for i in order], dtype=int),
        rest=np.asarray(rest, dtype=float)[order],
        lengths=np.asarray(lengths, dtype=float)[order],
    )


def object_scale(world: np.ndarray) -> float:
    """The uniform scale of an object's 4x4 world matrix; ModelError if it is not uniform (within 0.1 %)."""
    scales = np.linalg.norm(np.asarray(world, dtype=float)[:3, :3], axis=0)
    if scales.min() <= 0.0 or scales.max() > 1.001 * scales.min():
        shown = ", ".join(f"{s:.4g}" for s in scales)
        raise ModelError(f"the armature object's scale is not uniform ({shown}): apply the scale first")
    return float(scales.mean())


def rigid_world(world: np.ndarray, local: np.ndarray) -> np.ndarray:
    """(..., 4, 4) rigid frames in world space of frames ``local`` in an object with uniformly scaled ``world``."""
    world = np.asarray(world, dtype=float)
    scale = object_scale(world)
    out = np.array(local, dtype=float)
    out[..., :3, :3] = (world[:3, :3] / scale) @ out[..., :3, :3]
    out[..., :3, 3] = out[..., :3, 3] @ world[:3, :3].T + world[:3, 3]
    return out


def rigid_local(world: np.ndarray, frames: np.ndarray) -> np.ndarray:
    """The inverse of :func:`rigid_world`: world-space rigid frames expressed in the object's (scaled) space."""
    world = np.asarray(world, dtype=float)
    scale = object_scale(world)
    rotation = world[:3, :3] / scale
    out = np.array(frames, dtype=float)
    out[..., :3, :3] = rotation.T @ out[..., :3, :3]
    out[..., :3, 3] = (out[..., :3, 3] - world[:3, 3]) @ rotation / scale
    return out


def unit(v: np.ndarray) -> np.ndarray:
    n = float(np.linalg.norm(v))
    return v / n if n > _TINY else np.zeros(3)


def rotation_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The smallest rotation (3x3) turning direction ``a`` onto direction ``b`` (identity for a zero vector)."""
    a, b = unit(np.asarray(a, dtype=float)), unit(np.asarray(b, dtype=float))
    if not a.any() or not b.any():
        return np.eye(3)
    axis = np.cross(a, b)
    s, c = float(np.linalg.norm(axis)), float(a @ b)
    if s < 1e-9:
        if c > 0.0:
            return np.eye(3)
        other = np.eye(3)[int(np.argmin(np.abs(a)))]  # half a turn about any axis across ``a``
        axis = unit(np.cross(a, other))
        return 2.0 * np.outer(axis, axis) - np.eye(3)
    k = axis / s
    skew = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + s * skew + (1.0 - c) * (skew @ skew)


def rigid(rotation: np.ndarray, position: np.ndarray) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = rotation, position
    return m


def rigid_inverse(m: np.ndarray) -> np.ndarray:
    """Inverse of a rigid 4x4 (or a stack of them)."""
    out = np.zeros_like(m)
    rt = np.swapaxes(m[..., :3, :3], -1, -2)
    out[..., :3, :3] = rt
    out[..., :3, 3] = -(rt @ m[..., :3, 3, None])[..., 0]
    out[..., 3, 3] = 1.0
    return out
