"""A manikin's reach envelope: the reach along every direction of a direction sphere, in balance and without it.

The directions are visited outward from straight ahead (breadth first over the sphere's triangle edges); each ray
starts from the reached pose of its farthest-reaching visited neighbour (continuation: a few iterations per test
instead of a cold solve). The reach without balance starts from the balanced one (that pose holds without balance
too, so it is never less). A final pass searches again, from a neighbour's pose, each ray that reaches clearly less
than a neighbour (a local solve can stall on a ray where its neighbours' poses get farther). Units: m, kg.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..model import Model
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

    def points(self, which: str = "balanced") -> np.ndarray:
        """(k, 3) world points m: the shoulder plus each direction times its reach."""
        radii = self.balanced if which == "balanced" else self.kinematic
        return self.shoulder + self.sphere.directions * radii[:, None]


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
) -> Envelope:
    """The envelope of ``model``'s ``side`` hand over ``sphere``'s directions (reach within ``tolerance`` m), holding
    ``load_kg`` in that hand, its orientation fixed to ``rotation`` (3x3, world) or free, the centre of pressure in
    the soles scaled by ``sole_scale`` (see :func:`reach_setup`); ``progress(done, total)`` after each direction."""
    t0 = time.perf_counter()
    tolerance = check_tolerance(tolerance)
    balanced = _Rays(reach_setup(model, side, load_kg, rotation, True, sole_scale), sphere, tolerance)
    kinematic = _Rays(reach_setup(model, side, load_kg, rotation, False, sole_scale), sphere, tolerance)
    first_guess = 0.8 * arm_length(model, side)
    order = visiting_order(sphere)
    for done, i in enumerate(order, 1):
        ray = balanced.from_neighbour(i, first_guess)
        if ray.reached:
            kinematic.search(i, ray.radius, ray.pose, known=True)
        else:
            kinematic.from_neighbour(i, first_guess)
        if progress is not None:
            progress(done, len(order))
    balanced.repair()
    for i, ray in enumerate(balanced.found):  # a balanced pose the repair found holds without balance too
        if ray.reached and ray.radius > kinematic.found[i].radius:
            kinematic.search(i, ray.radius, ray.pose, known=True)
    kinematic.repair()
    bal, kin = balanced.radii(), kinematic.radii()
    shoulder = balanced.setup.shoulder
    return Envelope(
        model.name, side, float(load_kg), rotation, float(sole_scale), shoulder, sphere, bal, kin,
        arm_length(model, side), balanced.tests + kinematic.tests, time.perf_counter() - t0,
        {"balanced": balanced.poses(), "kinematic": kinematic.poses()},
    )  # fmt: skip
