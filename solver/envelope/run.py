"""One reach run as a plain function of plain inputs, returning one plain row (for a study runner's process pool or
a Dask worker): ``reach_row(manikin, direction, ...)`` -> dict. It solves cold (from the zero pose), so a run does
not depend on any other; :func:`solver.envelope.sweep.sweep_envelope` visits a whole sphere with warm starts instead
(faster, and each ray starts from its neighbour's pose). Units: m, kg.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from functools import lru_cache

import numpy as np

from ..body.model import Model
from ..body.spatial import quat_to_matrix
from ..errors import UsageError
from .reach import FEET, ReachSetup, arm_length, check_tolerance, reach_setup, search_ray


@lru_cache(maxsize=32)
def _model(manikin: str) -> Model:
    from ..io.scenario.bodies import load_preset

    return load_preset(manikin)


@lru_cache(maxsize=64)
def _setup(manikin: str, hand: str, load_kg: float, rotation: tuple | None, balance: bool, sole: float,
           feet: str = "planted") -> ReachSetup:  # fmt: skip
    matrix = None if rotation is None else quat_to_matrix(np.array(rotation))
    return reach_setup(_model(manikin), hand, load_kg, matrix, balance, sole, feet)


def rotation_of(quaternion: Sequence[float] | None) -> tuple[float, ...] | None:
    """A fixed hand orientation as a (w, x, y, z) tuple (None: free); a UsageError line for anything else."""
    if quaternion is None:
        return None
    q = tuple(float(v) for v in quaternion)
    if len(q) != 4 or not np.all(np.isfinite(q)) or np.linalg.norm(q) < 1e-9:
        raise UsageError(f"--rotation: expected 4 finite numbers w,x,y,z (a non-zero quaternion), got {quaternion!r}")
    return q


def reach_row(
    manikin: str,
    direction: Sequence[float],
    hand: str = "right",
    load_kg: float = 0.0,
    balance: bool = True,
    rotation: Sequence[float] | None = None,
    tolerance: float = 0.02,
    sole_scale: float = 1.0,
    feet: str = "planted",
) -> dict:
    """How far ``manikin`` (a preset name or body TOML path) reaches with its ``hand`` ("right"/"left") along
    ``direction`` (3 numbers, world: z up, the manikin faces -y) from its shoulder, the ``feet`` "planted" or free
    to "step" (:mod:`solver.stance.limits`), holding ``load_kg``, in balance or not, the hand's orientation free or
    fixed to ``rotation`` (w, x, y, z), the centre of pressure in the soles scaled by ``sole_scale`` (1: whole soles).
    Stepping searches the planted reach first and goes on from its pose (so it never reaches less).

    The row: the inputs, ``reach_m`` (0 when not reached), ``reached``, ``planted_reach_m`` (the same with planted
    feet), the hand point ``hand_x/y/z`` and the shoulder ``shoulder_x/y/z`` (m, world), where each sole stands at
    the reach ``foot_l_x/y`` (m) and ``foot_l_yaw_deg`` (its turn about z; likewise ``foot_r``; empty when not
    reached), ``arm_length_m``, ``solves``, ``iterations`` and ``time_s``.
    """
    t0 = time.perf_counter()
    d = np.asarray(direction, dtype=float)
    if d.shape != (3,) or not np.all(np.isfinite(d)) or np.linalg.norm(d) < 1e-9:
        raise UsageError(f"direction: expected 3 finite numbers, not all zero, got {direction!r}")
    check_tolerance(tolerance)
    rot = rotation_of(rotation)
    planted = _setup(str(manikin), hand, float(load_kg), rot, bool(balance), float(sole_scale))
    setup = planted if feet == "planted" else _setup(str(manikin), hand, float(load_kg), rot, bool(balance),
                                                     float(sole_scale), feet)  # fmt: skip
    d = d / np.linalg.norm(d)
    arm = arm_length(setup.model, hand)
    base = ray = search_ray(planted, d, 0.8 * arm, None, tolerance=tolerance)
    if setup is not planted and base.reached:
        ray = search_ray(setup, d, base.radius, base.pose, known=True, tolerance=tolerance)
    point = setup.shoulder + ray.radius * d
    row = {"manikin": setup.model.name, "hand": hand, "dx": float(d[0]), "dy": float(d[1]), "dz": float(d[2]),
           "balance": bool(balance), "load_kg": float(load_kg), "sole_scale": float(sole_scale), "feet": feet,
           "orientation": "free" if rot is None else " ".join(f"{v:g}" for v in rot),
           "reach_m": float(ray.radius), "reached": ray.reached, "planted_reach_m": float(base.radius)}  # fmt: skip
    row |= {f"hand_{k}": float(v) for k, v in zip("xyz", point, strict=True)}
    row |= {f"shoulder_{k}": float(v) for k, v in zip("xyz", setup.shoulder, strict=True)}
    row |= _soles(setup.model, ray.pose)
    searches = [base] if ray is base else [base, ray]
    row |= {"arm_length_m": arm, "solves": sum(r.tests for r in searches),
            "iterations": sum(r.iterations for r in searches), "time_s": time.perf_counter() - t0}  # fmt: skip
    return row


def _soles(model: Model, pose: np.ndarray | None) -> dict:
    """Where each sole stands in ``pose``: ``foot_l_x``, ``foot_l_y`` (m, world) and ``foot_l_yaw_deg`` (its turn
    about z from straight ahead; likewise ``foot_r``); None each when there is no pose."""
    kin = None if pose is None else model.forward(pose)
    out = {}
    for foot in FEET:
        rotation, position = kin.tcp_frame(model.tcp(foot)) if kin is not None else (None, None)
        out[f"{foot}_x"] = None if kin is None else float(position[0])
        out[f"{foot}_y"] = None if kin is None else float(position[1])
        out[f"{foot}_yaw_deg"] = None if kin is None else float(np.degrees(np.arctan2(rotation[1, 0], rotation[0, 0])))
    return out
