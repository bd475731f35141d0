"""Builds a :class:`~solver.body.model.Model` from joints, links, masses and TCPs given by name."""

from __future__ import annotations

import numpy as np

from ..errors import ModelError
from .model import EXTERIOR_JOINTS, Model, Tcp


class ModelBuilder:
    """Collects joints, links and TCPs by name and produces a :class:`Model`."""

    def __init__(self, name: str, info: dict | None = None) -> None:
        self.name = name
        self.info = dict(info or {})
        self._joints: list[dict] = []
        self._link_index: dict[str, int] = {}
        self._tcps: list[dict] = []

    def add_joint(
        self,
        name: str,
        parent: str | None,
        axis: tuple[float, float, float],
        origin: tuple[float, float, float] = (0.0, 0.0, 0.0),
        *,
        limits: tuple[float, float] = (-np.inf, np.inf),
        prismatic: bool = False,
        neutral: float = 0.0,
        strength: tuple[float, float] = (np.inf, np.inf),
        range_weight: float = 1.0,
        link: str | None = None,
        mass: float = 0.0,
        com: tuple[float, float, float] = (0.0, 0.0, 0.0),
        origin_rotation: np.ndarray | None = None,
    ) -> str:
        """Add joint ``name`` moving a new link (named ``link`` or ``name``) hung from link ``parent``.

        ``origin`` is the joint position in the parent link frame (m), ``axis`` the joint axis in the new
        link frame, ``limits`` (lower, upper) in rad (m if prismatic), ``strength`` (negative, positive)
        muscle capacity in N*m, ``range_weight`` the joint's weight in the comfort's range term.
        Returns the link name.
        """
        link_name = link or name
        if link_name in self._link_index:
            raise ModelError(f"link '{link_name}' defined twice")
        if any(j["name"] == name for j in self._joints):
            raise ModelError(f"joint '{name}' defined twice")
        if parent is not None and parent not in self._link_index:
            raise ModelError(f"joint '{name}': unknown parent link '{parent}'")
        a = np.asarray(axis, dtype=float)
        if a.shape != (3,) or not np.isfinite(a).all() or np.linalg.norm(a) < 1e-9:
            raise ModelError(f"joint '{name}': axis must be a non-zero 3-vector")
        lo, hi = float(limits[0]), float(limits[1])
        if not lo <= neutral <= hi:
            raise ModelError(f"joint '{name}': neutral {neutral} outside limits [{lo}, {hi}]")
        if mass < 0:
            raise ModelError(f"joint '{name}': negative mass")
        self._link_index[link_name] = len(self._joints)
        self._joints.append(
            dict(
                name=name,
                link=link_name,
                parent=-1 if parent is None else self._link_index[parent],
                axis=a / np.linalg.norm(a),
                origin=np.asarray(origin, dtype=float),
                origin_rotation=np.eye(3) if origin_rotation is None else np.asarray(origin_rotation, float),
                lower=lo,
                upper=hi,
                prismatic=bool(prismatic),
                neutral=float(neutral),
                strength=(float(strength[0]), float(strength[1])),
                range_weight=float(range_weight),
                mass=float(mass),
                com=np.asarray(com, dtype=float),
            )
        )
        return link_name

    def set_mass(self, link: str, mass: float, com: tuple[float, float, float]) -> None:
        """Give an existing link its mass (kg) and center of mass (m, link frame)."""
        j = self._joints[self._link_index[link]]
        j["mass"], j["com"] = float(mass), np.asarray(com, dtype=float)

    def add_tcp(
        self,
        name: str,
        link: str,
        position: tuple[float, float, float],
        rotation: np.ndarray | None = None,
        sole: np.ndarray | None = None,
    ) -> None:
        """Add a TCP frame on ``link`` at ``position`` (m, link frame) with ``rotation`` (3x3, link frame)."""
        if link not in self._link_index:
            raise ModelError(f"TCP '{name}': unknown link '{link}'")
        self._tcps.append(dict(name=name, link=link, position=position, rotation=rotation, sole=sole))

    def add_exterior_root(self, pelvis_position: tuple[float, float, float], link: str = "pelvis") -> str:
        """Three prismatic then three revolute joints (z, x, y) from the world origin to ``link``.

        With all six values zero the root link sits at ``pelvis_position`` (m) with identity rotation.
        """
        parent = None
        for name, axis in zip(EXTERIOR_JOINTS[:3], np.eye(3), strict=True):
            parent = self.add_joint(name, parent, tuple(axis), prismatic=True, limits=(-10.0, 10.0), range_weight=0.0)
        parent = self.add_joint(
            "root_rz", parent, (0, 0, 1), pelvis_position, limits=(-4 * np.pi, 4 * np.pi), range_weight=0.0
        )
        parent = self.add_joint("root_rx", parent, (1, 0, 0), limits=(-np.pi, np.pi), range_weight=0.0)
        return self.add_joint("root_ry", parent, (0, 1, 0), limits=(-np.pi, np.pi), range_weight=0.0, link=link)

    def build(self) -> Model:
        js = self._joints
        if not js:
            raise ModelError(f"model '{self.name}' has no joints")
        tcps = {}
        for t in self._tcps:
            rot = np.eye(3) if t["rotation"] is None else np.asarray(t["rotation"], dtype=float)
            sole = None if t["sole"] is None else np.asarray(t["sole"], dtype=float).reshape(-1, 2)
            tcps[t["name"]] = Tcp(t["name"], self._link_index[t["link"]], rot, np.asarray(t["position"], float), sole)
        return Model(
            name=self.name,
            joint_names=tuple(j["name"] for j in js),
            link_names=tuple(j["link"] for j in js),
            parent=np.array([j["parent"] for j in js], dtype=int),
            prismatic=np.array([j["prismatic"] for j in js], dtype=bool),
            axis=np.array([j["axis"] for j in js]),
            origin_rotation=np.array([j["origin_rotation"] for j in js]),
            origin_position=np.array([j["origin"] for j in js]),
            lower=np.array([j["lower"] for j in js]),
            upper=np.array([j["upper"] for j in js]),
            neutral=np.array([j["neutral"] for j in js]),
            strength=np.array([j["strength"] for j in js]),
            range_weight=np.array([j["range_weight"] for j in js]),
            mass=np.array([j["mass"] for j in js]),
            com=np.array([j["com"] for j in js]),
            tcps=tcps,
            info=self.info,
        )
