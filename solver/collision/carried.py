"""A box carried between two TCPs (``[carried]`` in a scenario): where it is, and how it moves, from the two TCPs.

Its centre is the midpoint of the two TCPs, its x axis runs from the first TCP to the second, its z axis is as
near world up as that allows. ``size`` (m) is along x (between the hands), y (depth) and z (height). Units: m.

The solver keeps the body out of it (:class:`~solver.constraints.carried_clearance.CarriedClearance`): the box moves
with the hands, so a row's Jacobian needs the velocity of the box's material point at the closest point, which
:func:`carried_point_rows` gives in terms of the two TCPs' velocities. Pictures and the .blend show the box.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..body.model import Tcp
from ..body.state import State
from ..kernels.carried import carried_jacobian
from . import Box
from .closest import cross, dot

CLEARANCE = 0.0  # m: the body may touch the box (a box carried against the belly) but not enter it


@dataclass(frozen=True)
class Carried:
    """A box of ``size`` (m: across the hands, depth, height) held between the TCPs ``tcps`` (first, second)."""

    size: np.ndarray
    tcps: tuple[str, str]
    name: str = "carried box"


def _up(x) -> np.ndarray:
    """The reference the z axis is made square to: world up, or world y for a near-vertical x."""
    return np.array([0.0, 0.0, 1.0]) if abs(x[2]) < 0.99 else np.array([0.0, 1.0, 0.0])


def carried_frame(first: np.ndarray, second: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(centre (3,) m, rotation (3, 3): columns x, y, z) of a box held between the points ``first`` and
    ``second`` (m, world). Upright: x from first to second, z world up made square to x; a vertical x (the hands
    one above the other) takes world y as its reference instead."""
    first, second = np.asarray(first, dtype=float), np.asarray(second, dtype=float)
    # plain floats: called at every trial pose of a solve, where NumPy's per-call cost on 3-vectors dominates
    dx, dy, dz = (second - first).tolist()
    length = max(math.sqrt(dx * dx + dy * dy + dz * dz), 1e-12)
    x = (dx / length, dy / length, dz / length)
    ux, uy, uz = (0.0, 0.0, 1.0) if abs(x[2]) < 0.99 else (0.0, 1.0, 0.0)  # as _up
    along = ux * x[0] + uy * x[1] + uz * x[2]
    z = (ux - along * x[0], uy - along * x[1], uz - along * x[2])
    size = math.sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2])
    z = (z[0] / size, z[1] / size, z[2] / size)
    y = (z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0])  # z cross x
    return (first + second) / 2.0, np.array([x, y, z]).T


def carried_box(carried: Carried, first: np.ndarray, second: np.ndarray) -> Box:
    """The carried box as a :class:`~solver.collision.Box` when its TCPs are at ``first`` and ``second`` (m)."""
    centre, rotation = carried_frame(first, second)
    return Box(centre, carried.size, rotation, name=carried.name)


def carried_point_rows(first: np.ndarray, second: np.ndarray, rotation: np.ndarray, local: np.ndarray,
                       normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """(n1, n2), each (k, 3): n . (velocity of the box's material point at ``local`` (k, 3), box coordinates, m) =
    n1 . p1' + n2 . p2' for the TCP velocities p1', p2' (``first``, ``second``: the TCPs, m; ``rotation`` their
    :func:`carried_frame`; ``normal`` (k, 3)).

    With d = p2 - p1, L = |d|, x = d / L, u the up reference, w = u - x (u.x), z = w / |w|, y = z x x, the point
    q = c + R b moves at c' + R' b, c' = (p1' + p2') / 2, and
    x' = (I - x x^T) d' / L,  z' = -(I - z z^T) ((u.x) I + x u^T) x' / |w|,  y' = z' x x + z x x',
    so n . R' b = x'.(b_x n + b_y n x z) + z'.(b_z n + b_y x x n) = h . d' (h below), and n1 = n/2 - h, n2 = n/2 + h.
    """
    length = max(float(np.linalg.norm(np.subtract(second, first))), 1e-12)
    x, z = rotation[:, 0], rotation[:, 2]
    u = _up(x)
    along = float(u @ x)
    s = math.sqrt(max(1.0 - along * along, 1e-24))  # |w|
    bx, by, bz = (local[:, i : i + 1] for i in range(3))
    a = bz * normal + by * cross(x, normal)  # n . R' b = x' . g0 + z' . a
    pa = a - z * dot(a, z)[:, None]  # (I - z z^T) a
    g = bx * normal + by * cross(normal, z) - (along * pa + u * dot(pa, x)[:, None]) / s  # M^T = (u.x) I + u x^T
    h = (g - x * dot(g, x)[:, None]) / length
    return normal / 2.0 - h, normal / 2.0 + h


def held_frame(state: State, tcps: tuple[Tcp, Tcp]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(the two TCPs' world positions (2, 3) m, the box's centre (3,) m and rotation (3, 3)) at ``state``, once per
    state (the body's and the obstacles' rows of the same box share it)."""
    key = ("carried box", tcps[0].name, tcps[1].name)
    got = state.cache.get(key)
    if got is None:
        kin = state.kin  # the positions of Kinematics.tcp_frame (its rotations are not needed here)
        held = np.array([kin.position[tcp.link] + kin.rotation[tcp.link] @ tcp.position for tcp in tcps])
        got = state.cache[key] = (held, *carried_frame(held[0], held[1]))
    return got


def box_motion_terms(state: State, tcps: tuple[Tcp, Tcp], on_box: np.ndarray,
                     normal: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    """n . (velocity of the box's material points at ``on_box`` (k, 3), world m) as point-velocity terms of the two
    TCPs: (links (2k,), points (2k, 3), directions (2k, 3)) for :meth:`~solver.body.model.Kinematics.jacobian_rows`; row
    i's derivative is the sum of terms i and k + i."""
    held, centre, rotation = held_frame(state, tcps)
    n1, n2 = carried_point_rows(held[0], held[1], rotation, (on_box - centre) @ rotation, normal)
    k = len(on_box)
    return np.repeat([t.link for t in tcps], k), np.repeat(held, k, axis=0), np.concatenate([n1, n2])


def _links_of(tcps: tuple[Tcp, Tcp]) -> np.ndarray:
    """The two TCPs' links (2,) int64, kept per pair of links (never written to)."""
    key = (tcps[0].link, tcps[1].link)
    found = _LINKS.get(key)
    if found is None:
        found = _LINKS[key] = np.array(key, dtype=np.int64)
    return found


_LINKS: dict[tuple[int, int], np.ndarray] = {}


def box_motion_jacobian(state: State, tcps: tuple[Tcp, Tcp], on_box: np.ndarray, normal: np.ndarray, n_x: int,
                        own: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None) -> np.ndarray:  # fmt: skip
    """(k, n_x) by the kernels: row i is n . (velocity of the box's material point at ``on_box[i]`` (world m)), n =
    ``normal[i]``, as :func:`box_motion_terms` gives it to :meth:`~solver.body.model.Kinematics.jacobian_rows`, plus
    with ``own`` = (points (k, 3) m, normals (k, 3), links (k,)) each point's n . velocity on its link (a body part's
    witness); zeros beyond the joints."""
    held, centre, rotation = held_frame(state, tcps)
    apart = held[1] - held[0]
    length = max(math.sqrt(apart.dot(apart)), 1e-12)  # np.linalg.norm's number (its dot, a correctly rounded root)
    k = len(on_box)
    out = np.zeros((k, n_x))
    links = _links_of(tcps)
    point, along, link = own if own is not None else (on_box, normal, np.full(k, -1, dtype=np.int64))
    flat = (np.ascontiguousarray(a, dtype=float) for a in (on_box, normal, point, along))
    box_on, box_normal, own_point, own_normal = flat
    carried_jacobian(held, centre, np.ascontiguousarray(rotation), length, box_on, box_normal, links, own_point,
                     own_normal, np.asarray(link, dtype=np.int64), state.kin.model.descendant, state.kin.twist,
                     out)  # fmt: skip
    return out
