"""Result file (JSON) -> typed :class:`~solver.io.frame.Frame` objects; every problem one ResultFileError line.

Only what the file holds is used (README "result JSON"): joints (``value``, ``min``, ``max``, ``type``,
``link``, ``strength``, world ``position`` and ``axis``), links (``name``, ``parent``, ``mass``, world ``com``),
TCPs (``position``, ``rotation`` (w, x, y, z), ``link``), ``gravity``, contacts (``point``, ``force``,
``moment`` about the point) and loads (``tcp``, ``point``, ``force``). Units: m, N, N*m, kg, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ResultFileError
from ..model import GRAVITY
from .files import read_json
from .frame import Frame
from .table_reader import TableReader

# bounds of a result file's values, far beyond any pose but small enough that products of them stay finite
LENGTH, FORCE, MASS, ANGLE = 1e4, 1e7, 1e4, 1e4  # m (positions), N and N*m, kg (a link), rad or m (joint values)


@dataclass
class ResultFile:
    """A read result file: where it is, the scenario it names (if any) and its frames."""

    path: Path | None
    scenario: str | None
    frames: list[Frame]


def read_result(path: str | Path) -> ResultFile:
    """Read and check a result file (written by ``python -m solver solve`` or :func:`solver.write_result`)."""
    path = Path(path)
    return result_from_dict(read_json(path, ResultFileError), path)


def result_from_dict(data: Any, path: str | Path = "result") -> ResultFile:
    """The parsed JSON ``data`` of a result file; ``path`` names it in error messages."""
    if not isinstance(data, dict):
        raise ResultFileError(f'{path}: expected a JSON object with a "frames" list, got {type(data).__name__}')
    root = TableReader(path, data, error=ResultFileError)
    frames = [_frame(t) for t in root.table_list("frames", non_empty=True)]
    scenario = data.get("scenario") if isinstance(data.get("scenario"), str) else None
    return ResultFile(Path(path) if isinstance(path, Path) else None, scenario, frames)


def frame_from_dict(raw: Any, where: str = "frame") -> Frame:
    """One result frame (a dict as in the file's ``frames`` list); ``where`` names it in error messages."""
    if not isinstance(raw, dict):
        raise ResultFileError(f"{where}: expected a result frame (an object), got {type(raw).__name__}")
    return _frame(TableReader(where, raw, error=ResultFileError))


def _frame(t: TableReader) -> Frame:
    t.required("joints", "links", "tcps")
    link_names, link_parent, mass, com = _links(t.table_list("links", non_empty=True))
    lindex = {n: i for i, n in enumerate(link_names)}
    joints = _joints(t.named_tables("joints"), lindex)
    tcp_position, tcp_rotation, tcp_link = {}, {}, {}
    for name, tcp in t.named_tables("tcps").items():
        tcp_position[name] = tcp.vector("position", 3, limit=LENGTH, unit="m")
        tcp_rotation[name] = tcp.rotation("rotation", [1.0, 0.0, 0.0, 0.0])
        tcp_link[name] = lindex[tcp.choice("link", lindex, "one of the links' names")]
    contacts = []
    for name, c in t.named_tables("contacts").items():
        if name not in tcp_link:
            raise t.fail(f"contacts.{name}", "a contact at one of the TCPs: " + ", ".join(sorted(tcp_link)))
        moment = c.vector("moment", 3, [0.0, 0.0, 0.0], limit=FORCE, unit="N*m")
        contacts.append(
            (name, c.vector("point", 3, limit=LENGTH, unit="m"), c.vector("force", 3, limit=FORCE, unit="N"), moment)
        )
    loads = []
    for ld in t.table_list("loads"):
        tcp = ld.choice("tcp", tcp_link, "a TCP name")
        loads.append((tcp, ld.vector("point", 3, limit=LENGTH, unit="m"), ld.vector("force", 3, limit=FORCE, unit="N")))
    converged = t.get("converged")
    return Frame(
        number=t.integer("frame", 1, -1e9, 1e9, "a whole frame number"),
        converged=converged if isinstance(converged, bool) else None,
        **joints,
        link_names=link_names,
        link_parent=link_parent,
        link_mass=mass,
        link_com=com,
        tcp_position=tcp_position,
        tcp_rotation=tcp_rotation,
        tcp_link=tcp_link,
        gravity=t.vector("gravity", 3, list(GRAVITY), limit=1e3, unit="m/s^2"),
        contacts=contacts,
        loads=loads,
        unmet=_names(t.get("unmet")),
        broken=_names(t.get("broken")),
    )


def _names(value) -> tuple[str, ...]:
    """A list of constraint names from the file (anything else: none)."""
    return tuple(v for v in value if isinstance(v, str)) if isinstance(value, list) else ()


def _links(links: list[TableReader]) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
    """Names, parent indices (-1: root or unknown parent), masses (kg) and world centres of mass (m)."""
    names = [lk.string("name") for lk in links]
    index = {n: i for i, n in enumerate(names)}
    parent = np.array([index.get(lk.get("parent"), -1) for lk in links], dtype=int)
    mass = np.array([lk.number("mass", low=0.0, high=MASS, unit="kg") for lk in links])
    com = np.array([lk.vector("com", 3, limit=LENGTH, unit="m") for lk in links]).reshape(-1, 3)
    return names, parent, mass, com


def _joints(joints: dict[str, TableReader], lindex: dict[str, int]) -> dict[str, Any]:
    """The joint arrays of :class:`Frame` (keyword arguments), in the file's order."""
    names, values, ranges, positions, axes, prismatic, links, strengths = [], [], [], [], [], [], [], []
    for name, jt in joints.items():
        names.append(name)
        values.append(jt.number("value", 0.0, -ANGLE, ANGLE))
        ranges.append([jt.limit("min", -math.inf, ANGLE), jt.limit("max", math.inf, ANGLE)])
        positions.append(jt.vector("position", 3, limit=LENGTH, unit="m"))
        axis = jt.vector("axis", 3, limit=LENGTH)
        if np.linalg.norm(axis) < 1e-9:
            raise jt.fail("axis", "a non-zero vector", axis.tolist())
        axes.append(axis / np.linalg.norm(axis))
        prismatic.append(jt.get("type") == "prismatic")
        links.append(lindex[jt.choice("link", lindex, "one of the links' names")])
        strengths.append(_strength(jt))
    has_strength = any(jt.get("strength") is not None for jt in joints.values())
    return dict(
        joint_names=names,
        joint_value=np.array(values),
        joint_range=np.array(ranges).reshape(-1, 2),
        joint_position=np.array(positions).reshape(-1, 3),
        joint_axis=np.array(axes).reshape(-1, 3),
        prismatic=np.array(prismatic, dtype=bool),
        joint_link=np.array(links, dtype=int),
        joint_strength=np.array(strengths).reshape(-1, 2) if has_strength else None,
    )


def _strength(jt: TableReader) -> list[float]:
    """[negative, positive] capacity (N*m), inf where the file says null (unlimited), NaN when not given."""
    value = jt.get("strength")
    if value is None:
        return [math.nan, math.nan]
    if not isinstance(value, list) or len(value) != 2:
        raise jt.fail("strength", "[negative, positive] capacities (numbers or null)", value)
    pair = jt.sub("strength", {"negative": value[0], "positive": value[1]})
    return [pair.limit(side, math.inf, FORCE, "N*m") for side in ("negative", "positive")]
