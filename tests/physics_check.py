"""The physics of a solve recomputed independently of solver/body/statics.py: total force and moment vanish, floors
only push inside their friction cones with the centre of pressure inside the sole, joints stay in range, every locked
axis of every target and loop is met, nothing is NaN (units: m, rad, N, N*m)."""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial.transform import Rotation

G = np.array([0.0, 0.0, -9.81])  # m/s^2, world
FORCE_TOL = 1.0  # N
MOMENT_TOL = 0.1  # N*m
POSITION_TOL = 1e-3  # m, per locked axis
ROTATION_TOL = math.radians(0.2)  # rad, per locked axis
AXES = ("x", "y", "z", "rx", "ry", "rz")
FEET_LOCK = ("z", "rx", "ry")


def tcp_frame(model, kin, name: str) -> tuple[np.ndarray, np.ndarray]:
    """World (rotation, origin) of a TCP, from the link frames of ``model.forward``."""
    tcp = model.tcps[name]
    r_link = kin.rotation[tcp.link]
    return r_link @ tcp.rotation, kin.position[tcp.link] + r_link @ tcp.position


def _locked_errors(r_target, o_target, r_tcp, o_tcp, lock) -> dict[str, float]:
    """Per locked axis: TCP origin in the target frame (m) and the rotation vector of R_T^T R (rad)."""
    pos = r_target.T @ (o_tcp - o_target)
    rot = Rotation.from_matrix(r_target.T @ r_tcp).as_rotvec()
    full = dict(zip(AXES, [*pos, *rot], strict=True))
    return {a: float(full[a]) for a in lock}


def _check_locks(label, errors, failures):
    for axis, value in errors.items():
        tol = POSITION_TOL if axis in ("x", "y", "z") else ROTATION_TOL
        if not abs(value) <= tol * (1 + 1e-6):
            unit = (value * 1e3, "mm") if axis in ("x", "y", "z") else (math.degrees(value), "deg")
            failures.append(f"{label}.{axis} off by {unit[0]:.4f} {unit[1]}")


def _inside_convex_polygon(point, corners, normal, tol=1e-6) -> bool:
    """``point`` inside the convex polygon ``corners`` (k x 3, world) seen along ``normal``."""
    k = len(corners)
    signs = [float(np.cross(corners[(i + 1) % k] - corners[i], point - corners[i]) @ normal) for i in range(k)]
    return all(s >= -tol for s in signs) or all(s <= tol for s in signs)


def assert_finite_result(result) -> None:
    bad = []
    if not np.isfinite(result.x).all():
        bad.append("x")
    for key, value in result.residuals.items():
        if not math.isfinite(value):
            bad.append(f"residual {key}={value}")
    if not math.isfinite(result.comfort):
        bad.append(f"comfort={result.comfort}")
    for key, value in result.comfort_parts.items():
        if not math.isfinite(value):
            bad.append(f"comfort part {key}={value}")
    if not np.isfinite(result.com).all():
        bad.append("com")
    for c in result.contacts:
        for key in ("point", "force", "moment"):
            if not np.isfinite(c[key]).all():
                bad.append(f"contact {c['tcp']} {key}")
    assert not bad, "non-finite values in the result: " + ", ".join(bad)


def check_physics(result) -> None:
    """Recompute the physics of ``result`` from the model, its joint values, contacts and loads; assert it holds."""
    assert_finite_result(result)
    problem = result.problem
    model = problem.model
    theta = np.asarray(result.theta, dtype=float)
    kin = model.forward(theta)
    zero = model.forward(model.zero_pose())
    failures: list[str] = []

    # joint ranges
    for name, value, lo, hi in zip(model.joint_names, theta, model.lower, model.upper, strict=True):
        if not lo - 1e-9 <= value <= hi + 1e-9:
            failures.append(f"joint {name} = {value:.6g} outside [{lo:.6g}, {hi:.6g}]")

    # targets and loops, on their locked axes
    for t in problem.targets:
        assert t.operator is None, "check_physics handles lock sets only"
        r_t = np.asarray(t.rotation, float) if t.rotation is not None else tcp_frame(model, zero, t.tcp)[0]
        r, o = tcp_frame(model, kin, t.tcp)
        _check_locks(t.tcp, _locked_errors(r_t, np.asarray(t.position, float), r, o, t.lock), failures)
    for lp in problem.loops:
        r_o, o_o = tcp_frame(model, kin, lp.other)
        offset_r = np.eye(3) if lp.offset_rotation is None else np.asarray(lp.offset_rotation, float)
        r_t, o_t = r_o @ offset_r, o_o + r_o @ np.asarray(lp.offset_position, float)
        r, o = tcp_frame(model, kin, lp.tcp)
        _check_locks(f"loop {lp.tcp}-{lp.other}", _locked_errors(r_t, o_t, r, o, lp.lock), failures)

    if not problem.balance:
        assert not result.contacts, "balance = False must not produce contact forces"
        assert not failures, "\n".join(failures)
        return

    # total force and moment about the world origin: gravity at link COMs, contact wrenches, loads
    com_world = kin.position + np.einsum("nij,nj->ni", kin.rotation, model.com)
    gravity = model.mass[:, None] * G[None, :]
    force = gravity.sum(axis=0)
    moment = np.cross(com_world, gravity).sum(axis=0)
    body_com = model.mass @ com_world / model.mass.sum()
    if np.linalg.norm(body_com - result.com) > 1e-6:
        failures.append(f"reported com {result.com} != recomputed {body_com}")
    for c in result.contacts:
        force = force + c["force"]
        moment = moment + np.cross(c["point"], c["force"]) + c["moment"]
    for ld in problem.loads:
        point = tcp_frame(model, kin, ld.tcp.name)[1]
        force = force + ld.force
        moment = moment + np.cross(point, ld.force)
    # "Converged" promises each balance row within its tolerance (solver/constraints/balance.py: 1 N and 0.1 N*m per
    # world axis), so the vector may reach sqrt(3) x that: checked per axis, as promised.
    if not np.max(np.abs(force)) <= FORCE_TOL:
        failures.append(f"total force {force} N (largest axis {np.max(np.abs(force)):.3f} N)")
    if not np.max(np.abs(moment)) <= MOMENT_TOL:
        failures.append(f"total moment {moment} N*m (largest axis {np.max(np.abs(moment)):.3f} N*m)")

    # contacts: push along the support normal, inside the friction cone, COP inside the sole
    supports = {t.tcp: t for t in problem.targets if t.support}
    reported = {c["tcp"] for c in result.contacts}
    if reported != set(supports):
        failures.append(f"contacts at {sorted(reported)}, supports are {sorted(supports)}")
    for c in result.contacts:
        t = supports[c["tcp"]]
        r_t = np.asarray(t.rotation, float) if t.rotation is not None else tcp_frame(model, zero, t.tcp)[0]
        normal = r_t[:, 2]
        f = np.asarray(c["force"], float)
        f_n = float(f @ normal)
        f_t = float(np.linalg.norm(f - f_n * normal))
        if np.linalg.norm(f) < 1e-6 and np.linalg.norm(c["moment"]) < 1e-6:
            continue  # an unloaded support (the other foot carries everything): allowed, nothing more to check
        if not f_n > 0.0:
            failures.append(f"contact {t.tcp}: normal force {f_n:.3f} N does not push")
            continue
        if not f_t <= t.friction * f_n * (1 + 1e-6) + 1e-6:
            failures.append(f"contact {t.tcp}: tangential {f_t:.3f} N > mu {t.friction} * normal {f_n:.3f} N")
        r_tcp, o_tcp = tcp_frame(model, kin, t.tcp)
        sole = t.sole if t.sole is not None else model.tcps[t.tcp].sole
        point = np.asarray(c["point"], float)
        m = np.asarray(c["moment"], float)
        if sole is None:
            if np.linalg.norm(point - o_tcp) > 1e-6:
                failures.append(f"contact {t.tcp}: point contact acts at {point}, TCP is at {o_tcp}")
            continue
        sole = np.asarray(sole, float).reshape(-1, 2)
        corners = o_tcp + np.column_stack([sole, np.zeros(len(sole))]) @ r_tcp.T
        if abs(float((point - o_tcp) @ r_tcp[:, 2])) > 1e-4:
            failures.append(f"contact {t.tcp}: COP {point} is off the sole plane")
        if not _inside_convex_polygon(point, corners, r_tcp[:, 2]):
            local = r_tcp.T @ (point - o_tcp)
            failures.append(f"contact {t.tcp}: COP {local[:2]} (TCP frame) outside the sole {sole.tolist()}")
        # about the COP the floor can only twist about its normal, and no more than friction allows
        m_n = float(m @ normal)
        m_tangential = float(np.linalg.norm(m - m_n * normal))
        if m_tangential > MOMENT_TOL:
            failures.append(f"contact {t.tcp}: moment about the COP has a tipping part of {m_tangential:.3f} N*m")
        reach = float(np.max(np.linalg.norm(corners - point, axis=1)))
        if abs(m_n) > t.friction * f_n * reach * (1 + 1e-6) + 1e-6:
            failures.append(f"contact {t.tcp}: twisting moment {m_n:.3f} N*m beyond friction")
    assert not failures, "\n".join(failures)
