"""Shared test helpers: a random tree model for derivative checks, and finite differences."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from solver.model import Model  # noqa: E402
from solver.model_builder import ModelBuilder  # noqa: E402


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
