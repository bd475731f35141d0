"""Forward kinematics of the benchmark's manikin three ways, and forward kinematics plus every constraint Jacobian of
one iteration, timed in one process with the cases taking turns (prints median and p95 per call, in ms).

    python -m bench.forward_kinematics [ROUNDS]
    python -m bench.forward_kinematics --pinocchio [ROUNDS]   # the compiled path against pinocchio (if it imports)

- ``Model.forward``: the shipped code (zero-offset chains composed first, then the chains by pointer jumping);
- level by level: every link at one depth of the tree in one batched product (one product per level);
- joint by joint: one 4x4 product per link in a Python loop.

The two references give the same frames as ``Model.forward`` (checked here to 1e-12); they are not shipped.

``--pinocchio``: issue 37's "forward kinematics plus all Jacobians of one iteration within 5x of pinocchio's on the
same model": the URDF export loaded by pinocchio; forward kinematics alone (``pin.forwardKinematics`` against
``Model.forward``), and forward kinematics with the TCP frames' Jacobians (``pin.computeJointJacobians`` +
``updateFramePlacements`` + ``getFrameJacobian`` per TCP, against ``Model.forward`` + the frame constraints' Jacobian
rows), each with the NumPy and the compiled kernels.
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


def _interleaved(cases: dict[str, Callable[[int], object]], rounds: int) -> dict[str, np.ndarray]:
    """µs per call of each case, the cases taking turns (each leads in turn)."""
    times: dict[str, list[float]] = {name: [] for name in cases}
    names = list(cases)
    for r in range(rounds):
        for name in names[r % len(names) :] + names[: r % len(names)]:
            t0 = time.perf_counter()
            cases[name](r)
            times[name].append(time.perf_counter() - t0)
    return {name: np.array(t[len(t) // 10 :]) * 1e6 for name, t in times.items()}  # the first tenth warms up


def pinocchio_side(rounds: int = 2000) -> str:
    """Ours (NumPy and compiled kernels) against pinocchio on the URDF export of the same model, µs per call."""
    import pinocchio as pin

    from solver import kernels
    from solver.constraints.frame import FrameGroup
    from solver.io.urdf import model_to_urdf

    model = rt.load_body(preset=rt.PRESET)
    pmodel = pin.buildModelFromXML(model_to_urdf(model))
    pdata = pmodel.createData()
    balance, groups = rt.CONFIGS["physics + reduction"]
    problem = rt.trial_problem(
        model, rt.draw_targets(model, rt.workspace_box(model), rt.LEVELS[3], 7000), balance, groups
    )
    frames = [c for c in problem.constraints if isinstance(c, FrameGroup)]
    tcp_names = [m.tcp.name for g in frames for m in g.members]
    frame_ids = [pmodel.getFrameId(f"tcp_{name}") for name in tcp_names]
    rng = np.random.default_rng(5)
    poses = [rng.uniform(model.lower, model.upper) for _ in range(16)]
    index = [pmodel.joints[pmodel.getJointId(name)].idx_q for name in model.joint_names]
    q_of = [np.zeros(pmodel.nq) for _ in poses]
    for q, theta in zip(q_of, poses, strict=True):
        q[index] = theta
    pin.forwardKinematics(pmodel, pdata, q_of[0])
    ours = model.forward(poses[0])
    lower = pdata.oMi[pmodel.getJointId(model.joint_names[-1])].translation
    assert np.allclose(lower, ours.position[-1], atol=1e-9), "pinocchio and ours disagree on the model"
    x_tail = problem.state(problem.start()).x[model.n :]

    def ours_jacobians(r: int) -> None:
        state = problem.state_of_x(np.concatenate([poses[r % 16], x_tail]))
        for group in frames:
            group.jacobian(state)

    def pin_jacobians(r: int) -> None:
        q = q_of[r % 16]
        pin.computeJointJacobians(pmodel, pdata, q)
        pin.updateFramePlacements(pmodel, pdata)
        for f in frame_ids:
            pin.getFrameJacobian(pmodel, pdata, f, pin.LOCAL_WORLD_ALIGNED)

    def with_kernels(flag: bool, call: Callable[[int], object]) -> Callable[[int], object]:
        def run_one(r: int) -> object:
            with kernels.using(flag):
                return call(r)

        return run_one

    cases: dict[str, Callable[[int], object]] = {
        "FK: ours, NumPy": with_kernels(False, lambda r: model.forward(poses[r % 16])),
        "FK: ours, compiled": with_kernels(True, lambda r: model.forward(poses[r % 16])),
        "FK: pinocchio": lambda r: pin.forwardKinematics(pmodel, pdata, q_of[r % 16]),
        "FK + TCP Jacobians: ours, NumPy": with_kernels(False, ours_jacobians),
        "FK + TCP Jacobians: ours, compiled": with_kernels(True, ours_jacobians),
        "FK + TCP Jacobians: pinocchio": pin_jacobians,
    }
    us = _interleaved(cases, rounds)
    lines = [
        f"{kernels.status()}; pinocchio {pin.__version__}; n = {model.n} joints, {len(tcp_names)} TCP frames "
        f"({', '.join(tcp_names)}); {rounds} calls each, interleaved; µs per call (median, p95, ratio to pinocchio)"
    ]
    for name, t in us.items():
        peer = us[name.split(":")[0] + ": pinocchio"]
        lines.append(f"{name}: {np.median(t):.1f} µs, p95 {np.percentile(t, 95):.1f}, "
                     f"{np.median(t) / np.median(peer):.1f}x pinocchio")  # fmt: skip
    return "\n".join(lines)


if __name__ == "__main__":
    one_core("bench.forward_kinematics")  # one core, one BLAS thread
    args = [a for a in sys.argv[1:] if a != "--pinocchio"]
    count = int(args[0]) if args else None
    if "--pinocchio" in sys.argv:
        print(pinocchio_side(count or 2000))
    else:
        print(run(count or 400))
