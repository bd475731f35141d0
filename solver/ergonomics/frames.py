"""Reading a result file (README "result JSON") into arrays, with one-line errors for bad input.

Only what the result file itself holds is used: joints (world ``position``, ``axis``, ``value``, ``type``,
``link``), links (``name``, ``parent``, ``mass``, world ``com``), TCPs (``position``, ``rotation`` (w, x, y, z),
``link``), contacts (``point``, ``force``, ``moment`` about the point) and loads (``tcp``, ``point``, ``force``).
Units: m, N, N*m, kg, rad.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ManikinError, read_text

GRAVITY_DEFAULT = (0.0, 0.0, -9.81)


class ErgonomicsInputError(ManikinError):
    """A result file that cannot be evaluated; the message is one line naming the file and the problem."""


def read_result(path: str | Path) -> dict:
    """Parse a result JSON file; every failure becomes one :class:`ErgonomicsInputError` line."""
    path = Path(path)
    text = read_text(path, ErgonomicsInputError)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ErgonomicsInputError(f"{path}: not JSON ({exc.msg} at line {exc.lineno})") from None
    frames = data.get("frames") if isinstance(data, dict) else None
    if not isinstance(frames, list) or not frames:
        raise ErgonomicsInputError(f'{path}: expected a result file with a non-empty "frames" list')
    return data


def _vec(where: str, value: Any, size: int = 3) -> np.ndarray:
    ok = isinstance(value, list) and len(value) == size
    ok = ok and all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in value)
    if not ok:
        raise ErgonomicsInputError(f"{where}: expected {size} finite numbers, got {value!r}")
    return np.asarray(value, dtype=float)


def _table(where: str, value: Any) -> dict:
    if not isinstance(value, dict):
        raise ErgonomicsInputError(f"{where}: expected an object, got {type(value).__name__}")
    return value


def quat_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrix of a quaternion (w, x, y, z); normalised first."""
    w, x, y, z = q / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


@dataclass
class Frame:
    """One result frame as arrays. Joint i moves link ``joint_link[i]``; ``below[j, k]``: link k in the subtree of
    link j (itself included)."""

    number: int
    converged: bool | None
    joint_names: list[str]
    joint_value: np.ndarray  # (n,) rad or m
    joint_range: np.ndarray  # (n, 2) lower, upper limit (rad or m), +-inf if none
    joint_position: np.ndarray  # (n, 3) m, world
    joint_axis: np.ndarray  # (n, 3) unit, world
    prismatic: np.ndarray  # (n,) bool
    joint_link: np.ndarray  # (n,) int, index into links
    joint_strength: list | None  # per joint [neg, pos] from the file, if present
    link_names: list[str]
    link_mass: np.ndarray  # (L,) kg
    link_com: np.ndarray  # (L, 3) m
    below: np.ndarray  # (L, L) bool
    tcp_position: dict[str, np.ndarray]
    tcp_rotation: dict[str, np.ndarray]
    tcp_link: dict[str, int]
    gravity: np.ndarray
    contacts: list[tuple[str, np.ndarray, np.ndarray, np.ndarray]]  # (tcp, point, force, moment)
    loads: list[tuple[str, np.ndarray, np.ndarray]]  # (tcp, point, force)
    index: dict[str, int] = field(default_factory=dict)

    def joint(self, name: str) -> int | None:
        """Index of joint ``name`` or None."""
        return self.index.get(name)

    def has(self, *names: str) -> bool:
        return all(n in self.index for n in names)

    def pos(self, name: str) -> np.ndarray:
        return self.joint_position[self.index[name]]

    def value(self, name: str) -> float:
        return float(self.joint_value[self.index[name]])


def parse_frame(raw: Any, where: str) -> Frame:
    """Validate one frame dict and turn it into a :class:`Frame`."""
    raw = _table(where, raw)
    for key in ("joints", "links", "tcps"):
        if key not in raw:
            raise ErgonomicsInputError(f'{where}: missing "{key}" (a result frame needs joints, links and tcps)')
    links = raw["links"]
    if not isinstance(links, list) or not links:
        raise ErgonomicsInputError(f"{where}.links: expected a non-empty list")
    link_names, parents, mass, com = [], [], [], []
    for i, lk in enumerate(links):
        w = f"{where}.links[{i}]"
        lk = _table(w, lk)
        if not isinstance(lk.get("name"), str):
            raise ErgonomicsInputError(f"{w}.name: expected a string")
        link_names.append(lk["name"])
        parents.append(lk.get("parent"))
        m = lk.get("mass")
        if isinstance(m, bool) or not isinstance(m, (int, float)) or not math.isfinite(m) or m < 0:
            raise ErgonomicsInputError(f"{w}.mass: expected a finite number >= 0, got {m!r}")
        mass.append(float(m))
        com.append(_vec(f"{w}.com", lk.get("com")))
    lindex = {n: i for i, n in enumerate(link_names)}
    parent = np.array([lindex.get(p, -1) if p is not None else -1 for p in parents], dtype=int)
    n_links = len(link_names)
    below = np.zeros((n_links, n_links), dtype=bool)
    for k in range(n_links):
        j, steps = k, 0
        while j >= 0 and steps <= n_links:
            below[j, k] = True
            j, steps = int(parent[j]), steps + 1
    joints = _table(f"{where}.joints", raw["joints"])
    names, values, ranges, positions, axes, prism, jlink, strengths = [], [], [], [], [], [], [], []
    for name, jt in joints.items():
        w = f"{where}.joints.{name}"
        jt = _table(w, jt)
        if jt.get("link") not in lindex:
            raise ErgonomicsInputError(f"{w}.link: expected one of the links' names, got {jt.get('link')!r}")
        names.append(name)
        v = jt.get("value", 0.0)
        values.append(float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else 0.0)
        lo, hi = jt.get("min"), jt.get("max")
        ranges.append(
            [
                float(lo) if isinstance(lo, (int, float)) else -math.inf,
                float(hi) if isinstance(hi, (int, float)) else math.inf,
            ]
        )
        positions.append(_vec(f"{w}.position", jt.get("position")))
        axis = _vec(f"{w}.axis", jt.get("axis"))
        norm = np.linalg.norm(axis)
        if norm < 1e-9:
            raise ErgonomicsInputError(f"{w}.axis: expected a non-zero vector")
        axes.append(axis / norm)
        prism.append(jt.get("type") == "prismatic")
        jlink.append(lindex[jt["link"]])
        strengths.append(jt.get("strength"))
    tcps = _table(f"{where}.tcps", raw["tcps"])
    tcp_pos, tcp_rot, tcp_link = {}, {}, {}
    for name, t in tcps.items():
        w = f"{where}.tcps.{name}"
        t = _table(w, t)
        tcp_pos[name] = _vec(f"{w}.position", t.get("position"))
        q = _vec(f"{w}.rotation", t.get("rotation", [1.0, 0.0, 0.0, 0.0]), 4)
        tcp_rot[name] = quat_matrix(q) if np.linalg.norm(q) > 1e-9 else np.eye(3)
        if t.get("link") not in lindex:
            raise ErgonomicsInputError(f"{w}.link: expected one of the links' names, got {t.get('link')!r}")
        tcp_link[name] = lindex[t["link"]]
    contacts = []
    for name, c in _table(f"{where}.contacts", raw.get("contacts", {})).items():
        w = f"{where}.contacts.{name}"
        if name not in tcp_link:
            raise ErgonomicsInputError(f"{w}: contact at an unknown TCP")
        c = _table(w, c)
        moment = _vec(f"{w}.moment", c.get("moment", [0.0, 0.0, 0.0]))
        contacts.append((name, _vec(f"{w}.point", c.get("point")), _vec(f"{w}.force", c.get("force")), moment))
    loads = []
    raw_loads = raw.get("loads", [])
    if not isinstance(raw_loads, list):
        raise ErgonomicsInputError(f"{where}.loads: expected a list")
    for i, ld in enumerate(raw_loads):
        w = f"{where}.loads[{i}]"
        ld = _table(w, ld)
        if ld.get("tcp") not in tcp_link:
            raise ErgonomicsInputError(f"{w}.tcp: expected a TCP name, got {ld.get('tcp')!r}")
        loads.append((ld["tcp"], _vec(f"{w}.point", ld.get("point")), _vec(f"{w}.force", ld.get("force"))))
    gravity = _vec(f"{where}.gravity", raw.get("gravity", list(GRAVITY_DEFAULT)))
    number = raw.get("frame", 1)
    return Frame(
        number=int(number) if isinstance(number, (int, float)) and not isinstance(number, bool) else 1,
        converged=raw.get("converged") if isinstance(raw.get("converged"), bool) else None,
        joint_names=names,
        joint_value=np.array(values),
        joint_range=np.array(ranges).reshape(-1, 2),
        joint_position=np.array(positions).reshape(-1, 3),
        joint_axis=np.array(axes).reshape(-1, 3),
        prismatic=np.array(prism, dtype=bool),
        joint_link=np.array(jlink, dtype=int),
        joint_strength=strengths if any(s is not None for s in strengths) else None,
        link_names=link_names,
        link_mass=np.array(mass),
        link_com=np.array(com).reshape(-1, 3),
        below=below,
        tcp_position=tcp_pos,
        tcp_rotation=tcp_rot,
        tcp_link=tcp_link,
        gravity=gravity,
        contacts=contacts,
        loads=loads,
        index={n: i for i, n in enumerate(names)},
    )


def parse_frames(data: dict, where: str = "result") -> list[Frame]:
    """All frames of a parsed result file."""
    return [parse_frame(f, f"{where}: frames[{i}]") for i, f in enumerate(data["frames"])]
