"""Shared test helpers: a random tree model for derivative checks, and finite differences."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from solver.body.builder import ModelBuilder  # noqa: E402
from solver.body.model import Model  # noqa: E402
from solver.io.result.frame import Frame  # noqa: E402


def random_tree(seed: int, n_interior: int = 14) -> Model:
    """Exterior root + a random branching tree with random axes, offsets, masses, a prismatic joint and TCPs."""
    rng = np.random.default_rng(seed)
    b = ModelBuilder(f"random{seed}")
    links = [b.add_exterior_root((0.0, 0.0, 1.0), link="pelvis")]
    b.set_mass("pelvis", 3.0, (0.0, 0.01, 0.05))
    for i in range(n_interior):
        parent = links[int(rng.integers(len(links)))]
        axis = rng.normal(size=3)
        name = b.add_joint(
            f"j{i}",
            parent,
            tuple(axis),
            tuple(rng.normal(scale=0.2, size=3)),
            limits=(-2.0, 2.5),
            prismatic=bool(i == 3),
            neutral=0.1,
            strength=(50.0 + 10 * i, 80.0),
            range_weight=0.5 + rng.random(),
            mass=float(rng.uniform(0.5, 4.0)),
            com=tuple(rng.normal(scale=0.1, size=3)),
        )
        links.append(name)
    for k, link in enumerate(links[-4:]):
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        q *= np.sign(np.linalg.det(q))
        sole = [[-0.1, -0.05], [0.1, -0.05], [0.1, 0.05], [-0.1, 0.05]] if k < 2 else None
        b.add_tcp(f"t{k}", link, tuple(rng.normal(scale=0.1, size=3)), q, sole)
    return b.build()


def finite_difference(fun, x: np.ndarray, eps: float = 1e-6) -> np.ndarray:
    """Central differences of a vector function: (len(f), len(x))."""
    cols = []
    for i in range(len(x)):
        dx = np.zeros_like(x)
        dx[i] = eps
        cols.append((np.asarray(fun(x + dx)) - np.asarray(fun(x - dx))) / (2 * eps))
    return np.array(cols).T


def states_on_one_kinematics(problem, x: np.ndarray) -> tuple:
    """(NumPy state, compiled-path state) of the full ``x`` on the same kinematics: the NumPy forward pass's arrays
    (strided views, as that path makes them) and contiguous copies of them (as the forward kernel makes them). The
    statics and comfort kernels are compared on these; the forward kernel agrees with NumPy's only to rounding."""
    import pytest

    from solver import kernels
    from solver.body.model import Kinematics

    with kernels.using(True):
        if not kernels.active():  # both paths would be NumPy's, on arrays laid out differently
            pytest.skip("compiled kernels are off in this process (MANIKIN_KERNELS=numpy)")
    with kernels.using(False):
        reference = problem.state_of_x(x)
        kin = reference.kin
    compiled = problem.state_of_x(x)
    copies = (np.ascontiguousarray(a) for a in (kin.rotation, kin.position, kin.axis, kin.com))
    compiled.__dict__["kin"] = Kinematics(kin.model, kin.theta, *copies)
    return reference, compiled


def same_frames(a: Frame, b: Frame) -> None:
    """Equal up to the quaternion round trip of the TCP rotations (the file holds quaternions)."""
    assert (a.number, a.converged, a.joint_names, a.link_names) == (b.number, b.converged, b.joint_names, b.link_names)
    for name in ("joint_value", "joint_range", "joint_position", "joint_axis", "prismatic", "joint_link",
                 "joint_strength", "link_parent", "link_mass", "link_com", "below", "gravity"):  # fmt: skip
        np.testing.assert_allclose(getattr(a, name), getattr(b, name), atol=1e-12, err_msg=name)
    assert a.tcp_link == b.tcp_link and a.tcp_position.keys() == b.tcp_position.keys()
    for tcp in a.tcp_position:
        np.testing.assert_allclose(a.tcp_position[tcp], b.tcp_position[tcp], atol=1e-12)
        np.testing.assert_allclose(a.tcp_rotation[tcp], b.tcp_rotation[tcp], atol=1e-12)
    assert [c[0] for c in a.contacts] == [c[0] for c in b.contacts] and len(a.loads) == len(b.loads)
    for x, y in zip(a.contacts + a.loads, b.contacts + b.loads, strict=True):
        assert x[0] == y[0]
        for u, v in zip(x[1:], y[1:], strict=True):
            np.testing.assert_allclose(u, v, atol=1e-12)


def leaves(report: object, path: str = "") -> dict:
    """{path: value} of every leaf of a report, for comparisons up to rounding (the file rounds axes, rotations)."""
    if isinstance(report, dict):
        return {k: v for key, item in report.items() for k, v in leaves(item, f"{path}.{key}").items()}
    if isinstance(report, list):
        return {k: v for i, item in enumerate(report) for k, v in leaves(item, f"{path}[{i}]").items()}
    return {path: report}


OBSTACLES_TOML = """
[[obstacles]]
name = "table"
kind = "box"
center = [0.0, -0.55, 0.4]
size = [0.8, 0.4, 0.8]
clearance = 0.01

[[obstacles]]
name = "ball"
kind = "sphere"
center = [1.0, 1.0, 1.0]
radius = 0.1

[[obstacles]]
name = "rail"
kind = "capsule"
a = [1.0, 0.0, 1.0]
b = [1.0, 1.0, 1.0]
radius = 0.02

[[obstacles]]
name = "wall"
kind = "plane"
point = [0.0, 2.0, 0.0]
normal = [0.0, -1.0, 0.0]

[[obstacles]]
name = "plate"
kind = "mesh"
vertices = [[2.0, 2.0, 0.0], [3.0, 2.0, 0.0], [2.0, 3.0, 0.0]]
faces = [[0, 1, 2]]

[[obstacles]]
name = "cube"
kind = "mesh"
file = "cube.obj"
"""  # a scenario's obstacles of every kind (appended to a scenario TOML)


def close_to_rounding(a, b) -> None:
    """``a`` equals ``b`` to 1e-12 relative to ``b``'s size (a compiled kernel against its NumPy twin)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape
    np.testing.assert_allclose(a, b, rtol=0.0, atol=1e-12 * max(1.0, float(np.max(np.abs(b), initial=0.0))))
