"""Static loads on the tree: balance residual, joint moments and their exact derivatives.

Every external force is a point force: gravity m_i g at each link COM, contact forces at sole corners,
user loads at TCPs. With per-link sums pushed up the tree (subtree sums ``S``), for joint j at p_j with
world axis a_j:

* moment of its subtree about p_j:  M_j = S_L[j] - p_j x S_F[j]     (thesis eq. 3.11)
* load about its axis:              tau_j = a_j . M_j  (a_j . S_F[j] for a prismatic joint)
* d(total moment)/d theta_j:        G_j = sum_k (a_j x (q_k - p_j)) x F_k   (eq. 3.7), a_j x S_F[j] if prismatic
* d tau_i / d theta_j:              a_j . G_i if j is i or an ancestor of i (revolute j), a_i . G_j if j is a
                                    descendant of i, else 0.

All forces are constant in the world frame (gravity, loads, cone edges fixed to the target frames), which
is what makes these formulas exact. Units: N, N*m, m.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .. import kernels
from ..kernels import statics as loops
from .contacts import ContactSet
from .model import GRAVITY, Kinematics, Model, Tcp
from .spatial import cross

_ROW = np.repeat(np.arange(3), 3)  # i of the row-major (i, j) pairs of a 3x3 matrix
_COL = np.tile(np.arange(3), 3)  # j


def _outer_rows(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """(m, 9) row-major outer products u_k v_k^T of (m, 3) rows."""
    return u.take(_ROW, axis=1) * v.take(_COL, axis=1)


_SYM_I, _SYM_J = np.array([0, 1, 2, 0, 0, 1]), np.array([0, 1, 2, 1, 2, 2])
_SYM_SCALE = np.array([1.0, 1.0, 1.0, 2.0, 2.0, 2.0]) ** 0.5


def _with_squares(u: np.ndarray) -> np.ndarray:
    """(m, 9) rows [u, s(u)] of (m, 3) rows u, where s(u) . s(v) = (u . v)^2 (the symmetric outer product u u^T
    with its off-diagonal pairs folded, times sqrt 2), so sums of u u^T need 6 columns instead of 9."""
    return np.concatenate([u, u.take(_SYM_I, axis=1) * u.take(_SYM_J, axis=1) * _SYM_SCALE], axis=1)


@dataclass(frozen=True)
class Load:
    """An external force (N, world frame) applied at a TCP, e.g. a carried box's weight."""

    tcp: Tcp
    force: np.ndarray


class StaticsLayout:
    """What stays fixed for one problem: which link every point force acts on, and the tree's incidence."""

    def __init__(self, model: Model, contacts: ContactSet, loads: list[Load]) -> None:
        self.model = model
        self.contacts = contacts
        self.loads = list(loads)
        n = model.n
        extra_links = np.concatenate([contacts.corner_link, np.array([ld.tcp.link for ld in loads], dtype=int)])
        # [i, k] = 1 if extra point k (sole corners, then loads) acts on link i; link COMs are points 0..n-1
        self.extra_on_link = (np.arange(n)[:, None] == extra_links[None, :]).astype(float)
        desc = model.descendant.astype(float)
        self.load_local = np.array([ld.tcp.position for ld in loads]).reshape(-1, 3)
        self.load_link = np.array([ld.tcp.link for ld in loads], dtype=int)
        self.load_force = np.array([ld.force for ld in loads], dtype=float).reshape(-1, 3)
        self.gravity_force = model.mass[:, None] * GRAVITY[None, :]
        self.gravity_total = model.total_mass * GRAVITY
        rev = ~model.prismatic
        self.ancestor_or_self_rev = desc.T * rev[None, :]  # [i, j]: j is i or an ancestor, j revolute
        self.strict_descendant = desc - np.eye(n)  # [i, j]: j strictly below i
        # [i, e]: contact edge variable e pushes on the subtree of joint i
        self.edge_acts = desc[:, contacts.corner_link[contacts.var_corner]]
        self.supporting = np.flatnonzero(self.edge_acts.any(axis=1))  # joints between the root and a support
        self.supporting_edge_acts = self.edge_acts[self.supporting]
        self.revolute = rev.astype(float)  # (n,) 1.0 for a revolute joint, 0.0 for a prismatic one
        self.supporting_revolute = self.revolute[self.supporting]  # the flags of the joints the forces move
        self.has_prismatic = bool(model.prismatic.any())
        # the compiled kernels' constants: links in preorder, the tree sums' tables, the point forces' links and places
        tree = model.tree_sums
        ints = (tree.order, model.parent, extra_links, contacts.var_corner, tree.start, tree.end, tree.after)
        ints += (tree.by_end, tree.closed_before)
        order, parent, point_link, var_corner, start, end, after, by_end, closed_before = (
            np.ascontiguousarray(a, dtype=np.int64) for a in ints
        )
        floats = (self.gravity_force, contacts.var_direction, self.load_force)
        gravity_force, var_direction, load_force = (np.ascontiguousarray(a, dtype=float) for a in floats)
        point_local = np.ascontiguousarray(np.concatenate([contacts.corner_local, self.load_local]), dtype=float)
        gravity = np.concatenate([self.gravity_total, GRAVITY]).astype(float)  # the totals' gravity terms
        self.prismatic = np.ascontiguousarray(model.prismatic, dtype=np.bool_)
        self.point_tables = (order, parent, gravity_force, point_link, point_local, var_corner, var_direction)
        by_link = np.argsort(point_link, kind="stable")  # each link's extra points, in their order
        link_first = np.searchsorted(point_link[by_link], np.arange(n + 1)).astype(np.int64)
        self.point_tables += (load_force, start, end, gravity, link_first, np.ascontiguousarray(by_link, np.int64))
        revolute = np.ascontiguousarray(self.revolute)
        self.contraction_tables = (order, revolute, start, end, after, by_end, closed_before)

    def subtree_sums(self, values: np.ndarray) -> np.ndarray:
        """(n, k): per joint, the sum of per-point ``values`` (link COMs, sole corners, loads; (points, k))
        over the points acting on its subtree."""
        n = self.model.n
        per_link = values[:n] + self.extra_on_link @ values[n:] if len(values) > n else values
        return self.model.tree_sums.subtree(per_link)

    def evaluate(self, kin: Kinematics, w: np.ndarray) -> Statics:
        return Statics(self, kin, w)


class Statics:
    """Point forces and their subtree sums for one state (joint values + contact weights)."""

    def __init__(self, layout: StaticsLayout, kin: Kinematics, w: np.ndarray) -> None:
        self.layout = layout
        self.kin = kin
        self.w = w
        self._g = None
        self._axis_loads: np.ndarray | None = None
        self._compiled = kernels.active()  # the kernels' state stays with the kernels (decided once per state)
        if self._compiled:
            self._fill_compiled()
            return
        contacts = layout.contacts
        self.corner_points = contacts.corner_points(kin)
        if len(layout.load_link):
            load_points = kin.position[layout.load_link] + np.einsum(
                "lij,lj->li", kin.rotation[layout.load_link], layout.load_local
            )
        else:
            load_points = layout.load_local  # (0, 3)
        self.load_points = load_points
        self._corner_forces = contacts.corner_forces(w)
        # Totals from the few point forces plus gravity at the whole-body COM (the balance error of every trial
        # point); the per-link forces and moments only when joint loads or derivatives need them.
        mass = layout.model.mass
        few_points = np.concatenate([(mass @ kin.com)[None, :], self.corner_points, load_points])
        few_forces = np.concatenate([GRAVITY[None, :], self._corner_forces, layout.load_force])
        self.total_force = layout.gravity_total + few_forces[1:].sum(axis=0)
        self.total_moment = cross(few_points, few_forces).sum(axis=0)  # about the world origin

    def _fill_compiled(self) -> None:
        """The kernel path of the constructor: points, forces, totals, subtree wrenches and axis loads in one loop."""
        kin, layout = self.kin, self.layout
        n, c = len(kin.com), len(layout.contacts.corner_link)
        points, forces = np.empty((len(layout.point_tables[4]), 3)), np.empty((len(layout.point_tables[4]), 3))
        totals, wrench, loads = np.empty(6), np.empty((n, 6)), np.empty(n)
        corner_forces = layout.contacts.corner_forces(self.w)  # BLAS's sums, as the NumPy path's
        body_com = layout.model.mass @ kin.com
        tables = layout.point_tables
        loops.point_loads(
            kin.rotation,
            kin.position,
            kin.com,
            corner_forces,
            body_com,
            tables,
            points,
            forces,
            totals,
            wrench,
            loads,
            kin.twist,
        )
        self._kernel_points, self._kernel_forces = points, forces
        self.corner_points, self.load_points, self._corner_forces = points[:c], points[c:], forces[:c]
        self.total_force, self.total_moment = totals[:3], totals[3:]
        self._totals = totals  # [force, moment]: the balance error's values, side by side already
        self.__dict__["_subtree_wrench"] = wrench  # what the cached property would compute
        self._axis_loads = loads

    @property
    def corner_forces(self) -> np.ndarray:
        """(c, 3) world force at each sole corner, N: :meth:`ContactSet.corner_forces` of the weights (not to be
        written to)."""
        return self._corner_forces

    def _compiled_derivatives(self) -> None:
        """The kernel path of :meth:`moment_derivatives`: G, the subtree outer sums, the edges' moment arms and the
        balance Jacobian's blocks in one loop."""
        kin, layout = self.kin, self.layout
        n, n_w = len(kin.com), layout.contacts.n_vars
        outer, g, arms = np.empty((n, 9)), np.empty((n, 3)), np.empty((n_w, 3))
        balance = np.empty((6, n + n_w))
        loops.moment_derivatives(
            kin.position,
            kin.axis,
            kin.com,
            self._kernel_points,
            self._kernel_forces,
            self._subtree_wrench,
            layout.point_tables,
            layout.prismatic,
            outer,
            g,
            arms,
            balance,
        )
        self.__dict__["sub_outer"], self.__dict__["edge_moment_arms"] = outer.reshape(n, 3, 3), arms
        self._balance_rows = balance
        self._g = g

    @cached_property
    def _points(self) -> np.ndarray:
        """(points, 3) where every force acts, m: link COMs, sole corners, loads."""
        return np.concatenate([self.kin.com, self.corner_points, self.load_points])

    @cached_property
    def _forces(self) -> np.ndarray:
        """(points, 3) the forces, N (world)."""
        return np.concatenate([self.layout.gravity_force, self._corner_forces, self.layout.load_force])

    @cached_property
    def _subtree_wrench(self) -> np.ndarray:
        """(n, 6) per joint: force (N) and moment about the world origin (N*m) of the loads on its subtree.

        Only joint loads and derivatives need it; the balance error (a trial point's) needs the totals alone."""
        return self.layout.subtree_sums(np.concatenate([self._forces, cross(self._points, self._forces)], axis=1))

    @property
    def sub_force(self) -> np.ndarray:
        """(n, 3) sum of the forces on each joint's subtree, N (world)."""
        return self._subtree_wrench[:, 0:3]

    @cached_property
    def sub_outer(self) -> np.ndarray:
        """(n, 3, 3) subtree sums of q_k F_k^T (point times force), N*m; only the derivatives need it."""
        return self.layout.subtree_sums(_outer_rows(self._points, self._forces)).reshape(-1, 3, 3)

    def axis_loads(self) -> np.ndarray:
        """(n,) component of the joint moment about the joint axis, N*m (axial force in N if prismatic)."""
        if self._axis_loads is None:  # a . (M - p x F) = a . M + (p x a) . F; a . F if prismatic
            self._axis_loads = np.einsum("ni,ni->n", self.kin.twist, self._subtree_wrench)
        return self._axis_loads

    def moment_derivatives(self) -> np.ndarray:
        """(n, 3) G_j = d(total moment)/d theta_j, N*m per rad (per m if prismatic)."""
        if self._g is None and self._compiled:
            self._compiled_derivatives()
        if self._g is None:
            a, p, sf = self.kin.axis, self.kin.position, self.sub_force
            a_dot_f = np.einsum("ni,ni->n", a, sf)
            trace = np.einsum("nii->n", self.sub_outer)
            w_rev = (
                np.einsum("nij,nj->ni", self.sub_outer, a)
                - p * a_dot_f[:, None]
                - a * (trace - np.einsum("ni,ni->n", p, sf))[:, None]
            )
            if self.layout.has_prismatic:
                prism = self.layout.model.prismatic_links
                w_rev[prism] = cross(a[prism], sf[prism])
            self._g = w_rev
        return self._g

    def balance_error(self) -> np.ndarray:
        """(6,) total force (N) and total moment about the world origin (N*m)."""
        if self._compiled:
            return self._totals.copy()  # the concatenation's values, in one copy
        return np.concatenate([self.total_force, self.total_moment])

    def balance_jacobian(self) -> tuple[np.ndarray, np.ndarray]:
        """d balance_error / d theta (6, n) and / d w (6, n_w)."""
        if self._compiled:
            rows, n = self.balance_rows(), self.layout.model.n
            return rows[:, :n], rows[:, n:]  # views of a fresh array
        d_theta = np.zeros((6, self.layout.model.n))
        d_theta[3:] = self.moment_derivatives().T
        d_w = np.concatenate([self.layout.contacts.var_direction.T, self.edge_moment_arms.T])
        return d_theta, d_w

    def balance_rows(self) -> np.ndarray:
        """(6, n + n_w) d balance_error / d x, x = [theta, w]: :meth:`balance_jacobian`'s blocks side by side."""
        if self._compiled:
            self.moment_derivatives()
            return self._balance_rows.copy()
        return np.hstack(self.balance_jacobian())

    @cached_property
    def edge_moment_arms(self) -> np.ndarray:
        """(n_w, 3) q x d per contact edge variable: moment about the world origin per unit weight, m."""
        contacts = self.layout.contacts
        return cross(self.corner_points[contacts.var_corner], contacts.var_direction)

    def axis_load_jacobian(self) -> tuple[np.ndarray, np.ndarray]:
        """d axis_loads / d theta (n, n) and / d w (n, n_w), exact; rows of prismatic joints are left 0."""
        layout = self.layout
        a = self.kin.axis
        g = self.moment_derivatives()
        d_theta = layout.ancestor_or_self_rev * (g @ a.T) + layout.strict_descendant * (a @ g.T)
        d_w = self._axis_load_force_jacobian()
        prism = layout.model.prismatic
        d_theta[prism] = 0.0
        d_w[prism] = 0.0
        return d_theta, d_w

    def _axis_load_force_jacobian(self, joints: np.ndarray | slice = slice(None), acts=None) -> np.ndarray:
        """d axis_loads / d w (n, n_w) of ``joints`` (all by default), prismatic rows included; ``acts``: the
        layout's ``edge_acts[joints]`` when the caller has it."""
        # a . (q x d) - (a x p) . d, with a x p = -(p x a), the joint's origin velocity
        kin, directions = self.kin, self.layout.contacts.var_direction
        return (self.layout.edge_acts[joints] if acts is None else acts) * (
            kin.axis[joints] @ self.edge_moment_arms.T + kin.origin_velocity[joints] @ directions.T
        )

    def axis_load_contractions(self, coef: np.ndarray, weight: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(coef @ J, weight @ (J * J)), both (n_x,), for J = d axis_loads / d x of :meth:`axis_load_jacobian`.

        Never forms the dense (n, n) block: with A = ancestor-or-self (revolute) and D = strict descendant,
        J_ij = A_ij g_i.a_j + D_ij a_i.g_j, and A, D are disjoint, so both sums are (n, n) @ (n, 9) products,
        done as subtree and ancestor sums.
        """
        layout = self.layout
        if self._compiled:  # the joints' part in one loop; the forces' part below, as BLAS sums it
            n, size = len(coef), len(coef) + layout.contacts.n_vars
            g, linear, squared = self.moment_derivatives(), np.empty(size), np.empty(size)
            coef, weight = (np.ascontiguousarray(v, dtype=float) for v in (coef, weight))
            work = np.empty((3, n + 1, 9))
            loops.load_contractions(self.kin.axis, g, coef, weight, layout.contraction_tables, work, linear, squared)
            if size > n:
                rows = layout.supporting
                d_w = self._axis_load_force_jacobian(rows, layout.supporting_edge_acts)
                revolute = layout.supporting_revolute
                coef_rev, weight_rev = coef[rows] * revolute, weight[rows] * revolute
                linear[n:], squared[n:] = coef_rev @ d_w, weight_rev @ (d_w * d_w)
            return linear, squared
        coef, weight = coef * layout.revolute, weight * layout.revolute
        # rows [a, s(a)], [g, s(g)]: on A, J_ij = g_i.a_j and J_ij^2 = s(g_i).s(a_j); on D, a and g swap
        n = len(coef)
        a_rows, g_rows = np.split(_with_squares(np.concatenate([self.kin.axis, self.moment_derivatives()])), [n])
        factor = np.empty_like(a_rows)  # coef for the J columns, weight for the J^2 columns
        factor[:, :3], factor[:, 3:] = coef[:, None], weight[:, None]
        # A^T X sums X over each joint's subtree (times its revolute flag)
        from_ancestors = layout.model.tree_sums.subtree(factor * g_rows)
        from_ancestors *= layout.revolute[:, None]
        # D^T Y sums Y over each joint's strict ancestors
        below = factor * a_rows
        from_descendants = layout.model.tree_sums.ancestors(below) - below
        both = from_ancestors * a_rows + from_descendants * g_rows
        lin_theta, sq_theta = both[:, :3].sum(axis=1), both[:, 3:].sum(axis=1)
        rows = layout.supporting  # the forces move only the loads of joints between the root and the supports
        d_w = self._axis_load_force_jacobian(rows, layout.supporting_edge_acts)
        lin_w, sq_w = coef[rows] @ d_w, weight[rows] @ (d_w * d_w)
        return np.concatenate([lin_theta, lin_w]), np.concatenate([sq_theta, sq_w])
