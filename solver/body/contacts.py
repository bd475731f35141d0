"""Unilateral contacts: a support's wrench as non-negative weights on friction-cone edges at sole corners.

Each support (a TCP standing on a target frame) gets its sole polygon's corners (a single point if it has
no sole) and, at every corner, four cone edges ``d = R_T (mu cos(phi), mu sin(phi), 1)``, phi = 0, 90, 180,
270 deg, in the target frame T (z = contact normal). A weight ``w >= 0`` on an edge is the normal force
(N) it carries. So "w >= 0" is all it takes for the floor to only push, for friction to stay inside the
(inscribed, linearised) cone of coefficient mu, and for the center of pressure to stay inside the sole.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .model import Kinematics, Model, Tcp
from .spatial import cross

EDGE_ANGLES = np.deg2rad([0.0, 90.0, 180.0, 270.0])


@dataclass(frozen=True)
class Support:
    """A TCP in contact with a surface whose normal is the z axis of ``normal_frame`` (3x3, world)."""

    tcp: Tcp
    normal_frame: np.ndarray
    friction: float
    sole: np.ndarray | None = None  # (k, 2) m in the TCP's x-y plane; None: the TCP's own sole or a point


@dataclass(frozen=True, eq=False)
class ContactSet:
    """All supports of a problem, flattened into corners and force variables (edge weights)."""

    supports: tuple[Support, ...]
    corner_link: np.ndarray  # (c,) link index of each corner
    corner_local: np.ndarray  # (c, 3) m, corner in its link frame
    corner_support: np.ndarray  # (c,) support index
    var_corner: np.ndarray  # (w,) corner of each force variable
    var_direction: np.ndarray  # (w, 3) world edge direction, z-component along the normal = 1
    corner_of_var: np.ndarray  # (c, w) 0/1 matrix summing edge forces into corner forces

    @property
    def n_vars(self) -> int:
        return len(self.var_corner)

    def corner_points(self, kin: Kinematics) -> np.ndarray:
        """(c, 3) world positions of all sole corners, m."""
        rot = kin.rotation[self.corner_link]
        return kin.position[self.corner_link] + np.einsum("cij,cj->ci", rot, self.corner_local)

    def corner_forces(self, w: np.ndarray) -> np.ndarray:
        """(c, 3) world force at each corner, N, for edge weights ``w``."""
        return self.corner_of_var @ (w[:, None] * self.var_direction)

    def even_weights(self, vertical_load: float) -> np.ndarray:
        """Equal edge weights whose world-z components carry ``vertical_load`` (N) together."""
        up = np.maximum(self.var_direction[:, 2], 0.0).sum()
        if self.n_vars == 0 or up <= 1e-9:
            return np.zeros(self.n_vars)
        return np.full(self.n_vars, max(vertical_load, 0.0) / up)

    def wrenches(
        self, kin: Kinematics, w: np.ndarray, points: np.ndarray | None = None, forces: np.ndarray | None = None
    ) -> list[dict]:
        """Per support: total force (N), center of pressure (m) and moment about it (N*m), world frame. ``points``,
        ``forces``: :meth:`corner_points` and :meth:`corner_forces` of ``kin`` and ``w`` when known (a state's
        statics has them)."""
        points = self.corner_points(kin) if points is None else points
        forces = self.corner_forces(w) if forces is None else forces
        out, cops = [], np.empty((len(self.supports), 3))
        for s, (support, corners, normal) in enumerate(self._support_corners):
            pts, fs = points[corners], forces[corners]
            pressure = fs @ normal
            load = float(np.add.reduce(pressure))  # ndarray.sum's own call, without its wrapper
            cops[s] = (pressure @ pts) / load if load > 1e-9 else pts.mean(axis=0)
            out.append(dict(tcp=support.tcp.name, point=cops[s], force=np.add.reduce(fs, axis=0)))
        arms = cross(points - cops[self.corner_support], forces)  # every corner's moment about its COP at once
        for wrench, (_, corners, _) in zip(out, self._support_corners, strict=True):
            wrench["moment"] = np.add.reduce(arms[corners], axis=0)
        return out

    @cached_property
    def _support_corners(self) -> list[tuple[Support, slice | np.ndarray, np.ndarray]]:
        """Per support: itself, its corners (a slice when adjacent, as :func:`build_contacts` makes them) and its
        normal (world, the z column of its frame)."""
        out = []
        for s, support in enumerate(self.supports):
            index = np.flatnonzero(self.corner_support == s)
            adjacent = len(index) and index[-1] - index[0] + 1 == len(index)
            corners = slice(int(index[0]), int(index[-1]) + 1) if adjacent else index
            out.append((support, corners, support.normal_frame[:, 2]))
        return out


def support_polygon(points: np.ndarray) -> np.ndarray:
    """Convex hull of contact points projected on the floor (world x-y), counter-clockwise, (k, 2) m.

    Andrew's monotone chain; collinear points are dropped. Fewer than three distinct points come back as given.
    """
    rows = sorted(set(map(tuple, np.asarray(points, dtype=float).reshape(-1, 3)[:, :2].round(12).tolist())))
    if len(rows) < 3:  # the distinct points, sorted as np.unique sorts rows
        return np.array(rows).reshape(-1, 2)

    def half(seq: list[tuple]) -> list[tuple]:  # Python floats: the same sums, no array per point
        out: list[tuple] = []
        for p in seq:
            while len(out) >= 2:
                (x0, y0), (x1, y1) = out[-2], out[-1]
                if (x1 - x0) * (p[1] - y0) - (y1 - y0) * (p[0] - x0) > 0:
                    break
                out.pop()
            out.append(p)
        return out

    lower, upper = half(rows), half(rows[::-1])
    return np.array(lower[:-1] + upper[:-1])


def build_contacts(model: Model, supports: list[Support]) -> ContactSet:
    """Flatten ``supports`` into corners and cone-edge force variables."""
    links, locals_, owners, var_corner, directions = [], [], [], [], []
    for s, support in enumerate(supports):
        tcp = support.tcp
        sole = support.sole if support.sole is not None else tcp.sole
        pts2 = np.zeros((1, 2)) if sole is None else np.asarray(sole, dtype=float).reshape(-1, 2)
        pts_tcp = np.column_stack([pts2, np.zeros(len(pts2))])
        for p in pts_tcp:
            c = len(links)
            links.append(tcp.link)
            locals_.append(tcp.position + tcp.rotation @ p)
            owners.append(s)
            for phi in EDGE_ANGLES:
                edge = np.array([support.friction * np.cos(phi), support.friction * np.sin(phi), 1.0])
                var_corner.append(c)
                directions.append(support.normal_frame @ edge)
    n_c, n_w = len(links), len(var_corner)
    corner_of_var = np.zeros((n_c, n_w))
    corner_of_var[np.asarray(var_corner, dtype=int), np.arange(n_w)] = 1.0
    return ContactSet(
        supports=tuple(supports),
        corner_link=np.asarray(links, dtype=int),
        corner_local=np.asarray(locals_, dtype=float).reshape(-1, 3),
        corner_support=np.asarray(owners, dtype=int),
        var_corner=np.asarray(var_corner, dtype=int),
        var_direction=np.asarray(directions, dtype=float).reshape(-1, 3),
        corner_of_var=corner_of_var,
    )
