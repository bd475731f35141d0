"""URDF export: valid XML with one joint per model joint, and the URDF's own kinematics (composed here from
its joint origins and axes, independently of the model code) equal ``model.forward`` at random poses."""

from __future__ import annotations

import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from helpers import random_tree

from solver.body.builder import ModelBuilder
from solver.io.scenario.bodies import load_body
from solver.io.urdf import link_inertia, matrix_from_rpy, model_to_urdf, rpy_from_matrix

REPO = Path(__file__).resolve().parents[3]


def _floats(text: str) -> np.ndarray:
    return np.array([float(v) for v in text.split()])


def _rot(rpy: np.ndarray) -> np.ndarray:
    """Rz(yaw) Ry(pitch) Rx(roll), written out again so the test does not trust the exporter's helper."""
    r, p, y = rpy
    rx = np.array([[1, 0, 0], [0, np.cos(r), -np.sin(r)], [0, np.sin(r), np.cos(r)]])
    ry = np.array([[np.cos(p), 0, np.sin(p)], [0, 1, 0], [-np.sin(p), 0, np.cos(p)]])
    rz = np.array([[np.cos(y), -np.sin(y), 0], [np.sin(y), np.cos(y), 0], [0, 0, 1]])
    return rz @ ry @ rx


def _axis_angle(axis: np.ndarray, angle: float) -> np.ndarray:
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


class UrdfTree:
    """The joints of a parsed URDF by child link, and forward kinematics by walking up to the root."""

    def __init__(self, text: str) -> None:
        self.root = ET.fromstring(text)
        self.by_child = {}
        for j in self.root.findall("joint"):
            origin = j.find("origin")
            axis = j.find("axis")
            self.by_child[j.find("child").get("link")] = dict(
                name=j.get("name"),
                type=j.get("type"),
                parent=j.find("parent").get("link"),
                xyz=_floats(origin.get("xyz")),
                rot=_rot(_floats(origin.get("rpy"))),
                axis=None if axis is None else _floats(axis.get("xyz")),
            )

    def frame(self, link: str, q: dict[str, float]) -> tuple[np.ndarray, np.ndarray]:
        """World rotation and position of ``link`` for joint values ``q`` (by joint name)."""
        rot, pos = np.eye(3), np.zeros(3)
        while link in self.by_child:
            j = self.by_child[link]
            r_local, p_local = j["rot"], j["xyz"].copy()
            if j["type"] == "revolute":
                r_local = r_local @ _axis_angle(j["axis"] / np.linalg.norm(j["axis"]), q[j["name"]])
            elif j["type"] == "prismatic":
                p_local = p_local + j["rot"] @ (j["axis"] * q[j["name"]])
            rot, pos = r_local @ rot, r_local @ pos + p_local
            link = j["parent"]
        assert link == "world"
        return rot, pos


def _rotated_origins_model():
    """A small model whose joint origins are rotated (the presets' are not), to exercise rpy."""
    rng = np.random.default_rng(7)
    b = ModelBuilder("rotated")
    parent = b.add_exterior_root((0.0, 0.0, 1.0))
    b.set_mass(parent, 5.0, (0.0, 0.0, 0.1))
    for i in range(6):
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        q *= np.sign(np.linalg.det(q))
        if i == 2:  # a gimbal-locked origin: pitch exactly 90 degrees
            q = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])
        parent = b.add_joint(
            f"j{i}", parent, tuple(rng.normal(size=3)), tuple(rng.normal(scale=0.2, size=3)), limits=(-2, 2),
            mass=1.0, com=(0.0, 0.05, 0.1), origin_rotation=q,
        )  # fmt: skip
    b.add_tcp("tip", parent, (0.1, 0.0, 0.0), _axis_angle(np.array([0.0, 0.6, 0.8]), 2.0))
    return b.build()


MODELS = {
    "male_50": lambda: load_body(preset="male_50"),
    "snake": lambda: load_body(preset="snake"),
    "random_tree": lambda: random_tree(3),
    "rotated_origins": _rotated_origins_model,
}


@pytest.mark.parametrize("name", sorted(MODELS))
def test_urdf_kinematics_equal_the_model_at_random_poses(name):
    model = MODELS[name]()
    tree = UrdfTree(model_to_urdf(model))
    rng = np.random.default_rng(11)
    lo, hi = np.maximum(model.lower, -3.0), np.minimum(model.upper, 3.0)
    for _ in range(5):
        theta = rng.uniform(lo, hi)
        kin = model.forward(theta)
        q = dict(zip(model.joint_names, theta, strict=True))
        for tcp_name, tcp in model.tcps.items():
            rot, pos = tree.frame(f"tcp_{tcp_name}", q)
            r_ref, p_ref = kin.tcp_frame(tcp)
            assert np.allclose(pos, p_ref, atol=1e-9), (name, tcp_name)
            assert np.allclose(rot, r_ref, atol=1e-9), (name, tcp_name)
        # whole-body center of mass from the URDF's inertial origins and masses
        total, moment = 0.0, np.zeros(3)
        for link in tree.root.findall("link"):
            inertial = link.find("inertial")
            if inertial is None:
                continue
            mass = float(inertial.find("mass").get("value"))
            rot, pos = tree.frame(link.get("name"), q)
            total += mass
            moment += mass * (pos + rot @ _floats(inertial.find("origin").get("xyz")))
        assert np.isclose(total, model.total_mass)
        assert np.allclose(moment / total, kin.body_com(), atol=1e-9)


def test_urdf_structure_names_limits_and_inertias():
    model = load_body(preset="male_50")
    root = ET.fromstring(model_to_urdf(model))
    assert root.tag == "robot" and root.get("name") == "male_50"
    joints = root.findall("joint")
    moving = [j for j in joints if j.get("type") != "fixed"]
    fixed = [j for j in joints if j.get("type") == "fixed"]
    assert len(moving) == model.n and len(fixed) == len(model.tcps)
    assert [j.get("name") for j in moving] == list(model.joint_names)
    assert [j.get("type") for j in moving[:3]] == ["prismatic"] * 3
    assert all(j.get("type") == "revolute" for j in moving[3:])
    assert moving[0].find("parent").get("link") == "world"
    links = [lk.get("name") for lk in root.findall("link")]
    assert len(links) == len(set(links)) == 1 + model.n + len(model.tcps)
    assert {f"tcp_{t}" for t in model.tcps} <= set(links)
    for j, lo, hi in zip(moving, model.lower, model.upper, strict=True):
        limit = j.find("limit")
        assert np.isclose(float(limit.get("lower")), lo) and np.isclose(float(limit.get("upper")), hi)
        assert float(limit.get("effort")) > 0 and float(limit.get("velocity")) > 0
    for i in np.nonzero(model.mass > 0)[0]:
        inertia = link_inertia(model, i)
        moments = np.linalg.eigvalsh(inertia)
        assert np.all(moments > 0) and moments[0] + moments[1] >= moments[2] * (1 - 1e-12)


def test_rpy_round_trip_including_gimbal_lock():
    rng = np.random.default_rng(3)
    for _ in range(50):
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        q *= np.sign(np.linalg.det(q))
        assert np.allclose(matrix_from_rpy(rpy_from_matrix(q)), q, atol=1e-12)
    for pitch in (np.pi / 2, -np.pi / 2):
        r = _rot(np.array([0.3, pitch, -0.4]))
        assert np.allclose(matrix_from_rpy(rpy_from_matrix(r)), r, atol=1e-9)


def test_cli_writes_the_urdf_and_refuses_bad_input(tmp_path):
    out = tmp_path / "snake.urdf"
    run = subprocess.run([sys.executable, "-m", "solver", "urdf", "snake", "-o", str(out)], cwd=REPO,
                         capture_output=True, text=True, timeout=60)  # fmt: skip
    assert run.returncode == 0, run.stderr
    assert ET.parse(out).getroot().tag == "robot"
    bad = subprocess.run([sys.executable, "-m", "solver", "urdf", "no_such_body", "-o", str(out)], cwd=REPO,
                         capture_output=True, text=True, timeout=60)  # fmt: skip
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1
