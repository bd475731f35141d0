"""A manikin's reach envelope: the reach along every direction of a direction sphere, in balance and without it.

The directions are visited outward from straight ahead (breadth first over the sphere's triangle edges); each ray
starts from the reached pose of its farthest-reaching visited neighbour (continuation: a few iterations per test
instead of a cold solve). The reach without balance starts from the balanced one (that pose holds without balance
too, so it is never less). A final pass searches again, from a neighbour's pose, each ray that reaches clearly less
than a neighbour (a local solve can stall on a ray where its neighbours' poses get farther). With stepping feet
each ray is also searched with the feet planted first, and the stepping search goes on from there when its
neighbours did not take it as far (stepping only loosens the planted problem, so it never reaches less). Units: m,
kg.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..body.model import Model
from .directions import DirectionSphere
from .reach import RayReach, ReachSetup, arm_length, check_tolerance, reach_setup, search_ray

AHEAD = np.array([0.0, -1.0, 0.0])  # the manikin faces -y
REPAIR_GAP = 0.04  # m: a ray this much shorter than a neighbour is searched again from that neighbour's pose
SEED_BACK = 0.06  # m: a ray's search starts this much short of its neighbour's reach (mostly reached at once)


@dataclass
class Envelope:
    """One manikin's envelope for one hand: per direction (rows of ``sphere.directions``) the ``balanced`` and
    ``kinematic`` (balance off) reach, m from the ``shoulder`` (world, zero pose); the straight ``arm`` length;
    the solves (``tests``) and ``time_s`` it took."""

    manikin: str
    side: str
    load_kg: float
    rotation: np.ndarray | None
    sole_scale: float
    shoulder: np.ndarray
    sphere: DirectionSphere
    balanced: np.ndarray
    kinematic: np.ndarray
    arm: float
    tests: int = 0
    time_s: float = 0.0
    poses: dict[str, list] = field(default_factory=dict)  # "balanced"/"kinematic": joint values per direction
    feet: str = "planted"  # or "step": the soles slide and turn on the floor within the stance bounds
    planted: np.ndarray | None = None  # stepping only: the reach in balance with the feet planted, per direction

    def radii(self, which: str = "balanced") -> np.ndarray:
        """The reach per direction (m) of ``which``: "balanced", "kinematic" or (stepping) "planted"."""
        radii = {"balanced": self.balanced, "kinematic": self.kinematic, "planted": self.planted}.get(which)
        if radii is None:
            raise ValueError(f"this envelope has no {which!r} reach")
        return radii

    def kinds(self) -> tuple[str, ...]:
        """The reaches this envelope has: balanced and kinematic, and planted when stepping."""
        return ("balanced", "kinematic") + (("planted",) if self.planted is not None else ())

    def points(self, which: str = "balanced") -> np.ndarray:
        """(k, 3) world points m: the shoulder plus each direction times its reach."""
        return self.shoulder + self.sphere.directions * self.radii(which)[:, None]


def visiting_order(sphere: DirectionSphere) -> list[int]:
    """The directions breadth first over the triangle edges, from the one nearest straight ahead."""
    near = sphere.neighbours()
    first = int(np.argmax(sphere.directions @ AHEAD))
    order, seen = [first], {first}
    for i in order:
        for j in sorted(near[i]):
            if j not in seen:
                seen.add(j)
                order.append(j)
    order += [i for i in range(len(sphere.directions)) if i not in seen]  # none on a geodesic sphere
    return order


class _Rays:
    """The reach found so far along each direction, for one setup."""

    def __init__(self, setup: ReachSetup, sphere: DirectionSphere, tolerance: float) -> None:
        self.setup, self.sphere, self.tolerance = setup, sphere, tolerance
        self.found: list[RayReach | None] = [None] * len(sphere.directions)
        self.near = sphere.neighbours()
        self.tests = 0

    def search(self, i: int, seed: float, pose: np.ndarray | None, known: bool = False, retry: bool = True) -> RayReach:
        """Search ray ``i`` (see :func:`search_ray`); keep the farther of what it finds and what was found before."""
        got = search_ray(self.setup, self.sphere.directions[i], seed, pose, known, self.tolerance, retry)
        self.tests += got.tests
        old = self.found[i]
        if old is None or got.radius > old.radius:
            self.found[i] = got
        return self.found[i]

    def from_neighbour(self, i: int, first_guess: float) -> RayReach:
        """Search ray ``i`` from its farthest-reaching visited neighbour (SEED_BACK short of its reach), or cold
        from ``first_guess`` m when none is reached."""
        near = self.best_neighbour(i)
        if near is None:
            return self.search(i, first_guess, None)
        return self.search(i, near.radius - SEED_BACK, near.pose)

    def best_neighbour(self, i: int) -> RayReach | None:
        """The visited neighbour of ``i`` that reaches farthest (None if none is reached)."""
        done = [self.found[j] for j in self.near[i] if self.found[j] is not None and self.found[j].reached]
        return max(done, key=lambda ray: ray.radius, default=None)

    def repair(self) -> None:
        """Each ray clearly shorter than a neighbour: if that neighbour's pose gets REPAIR_GAP farther along it (one
        test), search on from there. A ray not reached at all is searched from each reached neighbour in turn (its
        seeds nearer the shoulder may have been inside the body, where a ray through the trunk is not reached)."""
        for i, ray in enumerate(self.found):
            if not ray.reached:
                near = [self.found[j] for j in self.near[i] if self.found[j].reached]
                for other in sorted(near, key=lambda r: -r.radius):
                    if self.search(i, other.radius - SEED_BACK, other.pose, retry=False).reached:
                        break
                continue
            best = self.best_neighbour(i)
            if best is not None and best.radius > ray.radius + REPAIR_GAP:
                self.search(i, ray.radius + REPAIR_GAP, best.pose, retry=False)

    def radii(self) -> np.ndarray:
        return np.array([ray.radius for ray in self.found])

    def poses(self) -> list:
        return [None if ray.pose is None else ray.pose.tolist() for ray in self.found]


def sweep_envelope(
    model: Model,
    sphere: DirectionSphere,
    side: str = "right",
    load_kg: float = 0.0,
    rotation: np.ndarray | None = None,
    tolerance: float = 0.02,
    progress: Callable[[int, int], None] | None = None,
    sole_scale: float = 1.0,
    feet: str = "planted",
) -> Envelope:
    """The envelope of ``model``'s ``side`` hand over ``sphere``'s directions (reach within ``tolerance`` m), holding
    ``load_kg`` in that hand, its orientation fixed to ``rotation`` (3x3, world) or free, the centre of pressure in
    the soles scaled by ``sole_scale``, the ``feet`` "planted" or free to "step" (see :func:`reach_setup`);
    ``progress(done, total)`` after each direction. Stepping also searches the planted reach in balance
    (``Envelope.planted``) and starts each stepping ray from it, so a stepping reach is never shorter."""
    t0 = time.perf_counter()
    tolerance = check_tolerance(tolerance)

    def rays(in_balance: bool, mode: str) -> _Rays:
        return _Rays(reach_setup(model, side, load_kg, rotation, in_balance, sole_scale, mode), sphere, tolerance)

    balanced, kinematic = rays(True, feet), rays(False, feet)
    planted = rays(True, "planted") if feet != "planted" else None
    first_guess = 0.8 * arm_length(model, side)
    order = visiting_order(sphere)
    for done, i in enumerate(order, 1):
        ray = _visit(i, balanced, planted, first_guess)
        if ray.reached:
            kinematic.search(i, ray.radius, ray.pose, known=True)
        else:
            kinematic.from_neighbour(i, first_guess)
        if progress is not None:
            progress(done, len(order))
    if planted is not None:
        planted.repair()
    balanced.repair()
    _lift(planted, balanced)  # stepping reaches at least as far as the planted feet
    _lift(balanced, kinematic)  # a balanced pose the repair found holds without balance too
    kinematic.repair()
    searched = [r for r in (balanced, kinematic, planted) if r is not None]
    poses = {"balanced": balanced.poses(), "kinematic": kinematic.poses()}
    return Envelope(
        model.name, side, float(load_kg), rotation, float(sole_scale), balanced.setup.shoulder, sphere,
        balanced.radii(), kinematic.radii(), arm_length(model, side), sum(r.tests for r in searched),
        time.perf_counter() - t0, poses, feet, None if planted is None else planted.radii(),
    )  # fmt: skip


def _visit(i: int, rays: _Rays, planted: _Rays | None, first_guess: float) -> RayReach:
    """Search ray ``i`` of ``rays`` from its neighbours; when stepping, after the ray of the ``planted`` feet, from
    whose pose the stepping ray then goes on if its neighbours did not get it as far."""
    if planted is None:
        return rays.from_neighbour(i, first_guess)
    base = planted.from_neighbour(i, first_guess)
    ray = None
    if rays.best_neighbour(i) is not None or not base.reached:
        ray = rays.from_neighbour(i, first_guess)
    if base.reached and (ray is None or base.radius > ray.radius):
        ray = rays.search(i, base.radius, base.pose, known=True)
    return ray


def _lift(shorter: _Rays | None, longer: _Rays) -> None:
    """Each ray of ``longer`` (a looser setup: no balance, or stepping feet) that ``shorter`` reaches farther is
    searched on from ``shorter``'s pose there (it holds in ``longer``'s setup too)."""
    if shorter is None:
        return
    for i, ray in enumerate(shorter.found):
        if ray.reached and ray.radius > longer.found[i].radius:
            longer.search(i, ray.radius, ray.pose, known=True)
