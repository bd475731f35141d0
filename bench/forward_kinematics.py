"""Forward kinematics of the benchmark's manikin three ways, and forward kinematics plus every constraint Jacobian of
one iteration, timed in one process with the cases taking turns (prints median and p95 per call, in ms).

    python -m bench.forward_kinematics [ROUNDS]

- ``Model.forward``: the shipped code (zero-offset chains composed first, then the chains by pointer jumping);
- level by level: every link at one depth of the tree in one batched product (one product per level);
- joint by joint: one 4x4 product per link in a Python loop.

The two references give the same frames as ``Model.forward`` (checked here to 1e-12); they are not shipped.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable

import numpy as np

from solver.body.model import Model, _parents_first
from solver.body.spatial import skew

from . import one_core
from . import random_targets as rt


def local_frames(model: Model, theta: np.ndarray) -> np.ndarray:
    """(n, 4, 4) each link's frame in its parent link's frame at joint values ``theta`` (rad / m)."""
    k = skew(model.axis)
    rev = np.where(model.prismatic, 0.0, theta)[:, None, None]
    spin = np.eye(3) + np.sin(rev) * k + (1.0 - np.cos(rev)) * (k @ k)
    slide = np.where(model.prismatic, theta, 0.0)[:, None] * model.axis
    out = np.zeros((model.n, 4, 4))
    out[:, 3, 3] = 1.0
    out[:, :3, :3] = model.origin_rotation @ spin
    out[:, :3, 3] = model.origin_position + (model.origin_rotation @ slide[:, :, None])[:, :, 0]
    return out


def depth_levels(model: Model) -> list[np.ndarray]:
    """Links grouped by depth in the tree (roots first)."""
    depth = np.zeros(model.n, dtype=int)
    for j in _parents_first(model.parent):
        depth[j] = 0 if model.parent[j] < 0 else depth[model.parent[j]] + 1
    return [np.flatnonzero(depth == d) for d in range(depth.max() + 1)]


def level_by_level(model: Model, levels: list[np.ndarray], theta: np.ndarray) -> np.ndarray:
    """(n, 4, 4) world frames, one batched product per depth level."""
    world = local_frames(model, theta)
    for links in levels[1:]:
        world[links] = world[model.parent[links]] @ world[links]
    return world


def joint_by_joint(model: Model, order: list[int], theta: np.ndarray) -> np.ndarray:
    """(n, 4, 4) world frames, one 4x4 product per link."""
    world = local_frames(model, theta)
    for j in order:
        if model.parent[j] >= 0:
            world[j] = world[model.parent[j]] @ world[j]
    return world


def one_iteration(problem, x: np.ndarray) -> None:
    """Forward kinematics and every constraint's Jacobian rows at a fresh evaluation point, as one iteration does."""
    state = problem.state_of_x(x)
    for c in problem.constraints:
        c.jacobian_rows(state)


def run(rounds: int = 400) -> str:
    model = rt.load_body(preset=rt.PRESET)
    levels, order = depth_levels(model), _parents_first(model.parent)
    rng = np.random.default_rng(5)
    poses = [rng.uniform(model.lower, model.upper) for _ in range(16)]
    for theta in poses:  # the references compute the same frames
        kin, ref = model.forward(theta), level_by_level(model, levels, theta)
        assert np.allclose(ref[:, :3, :3], kin.rotation, atol=1e-12) and np.allclose(ref[:, :3, 3], kin.position)
        assert np.allclose(joint_by_joint(model, order, theta), ref, atol=1e-12)
    balance, groups = rt.CONFIGS["physics + reduction"]
    problem = rt.trial_problem(
        model, rt.draw_targets(model, rt.workspace_box(model), rt.LEVELS[3], 7000), balance, groups
    )
    x = problem.state(problem.start()).x  # [joints, forces] of the start
    cases: dict[str, Callable[[np.ndarray], object]] = {
        "Model.forward (chains, pointer jumping)": model.forward,
        "level by level (one product per depth)": lambda t: level_by_level(model, levels, t),
        "joint by joint (one product per link)": lambda t: joint_by_joint(model, order, t),
        "forward + all constraint Jacobians": lambda t: one_iteration(problem, np.concatenate([t, x[model.n :]])),
    }
    times: dict[str, list[float]] = {name: [] for name in cases}
    names = list(cases)
    for r in range(rounds):
        theta = poses[r % len(poses)]
        for name in names[r % len(names) :] + names[: r % len(names)]:  # each case leads in turn
            t0 = time.perf_counter()
            cases[name](theta)
            times[name].append(time.perf_counter() - t0)
    lines = [f"n = {model.n} joints, {len(levels)} depth levels, {len(model._fk.jumps)} pointer-jumping rounds over "
             f"{len(model._fk.chain_end)} chains; {rounds} calls each, interleaved"]  # fmt: skip
    for name, t in times.items():
        ms = np.array(t) * 1e3
        lines.append(f"{name}: median {np.median(ms):.3f} ms, p95 {np.percentile(ms, 95):.3f} ms")
    return "\n".join(lines)


if __name__ == "__main__":
    one_core("bench.forward_kinematics")  # one core, one BLAS thread
    print(run(int(sys.argv[1]) if len(sys.argv) > 1 else 400))
