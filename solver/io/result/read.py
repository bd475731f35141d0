"""Result file (JSON or compact) -> typed :class:`~solver.io.result.frame.Frame` objects; every problem one
ResultFileError
line. :class:`ResultStream` reads one frame at a time, :func:`read_result` all of them.

Only what the file holds is used (docs/reference/result-file.md): joints (``value``, ``min``, ``max``, ``type``,
``link``, ``strength``, world ``position`` and ``axis``), links (``name``, ``parent``, ``mass``, world ``com``),
TCPs (``position``, ``rotation`` (w, x, y, z), ``link``), ``gravity``, contacts (``point``, ``force``,
``moment`` about the point) and loads (``tcp``, ``point``, ``force``). A compact file holds the model once and per
frame the joint values; its world positions are those of the model's forward kinematics. Units: m, N, N*m, kg, rad.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass, replace
from itertools import chain
from pathlib import Path
from typing import Any

import numpy as np

from ...body.model import GRAVITY, Model
from ...errors import ManikinError, ResultFileError
from ..table_reader import TableReader
from .frame import Frame, frame_of_pose
from .model_json import model_from_dict
from .scan import FrameLine, UncheckedFrame, checked_frame, is_compact, parse_line, scan

# bounds of a result file's values, far beyond any pose but small enough that products of them stay finite
LENGTH, FORCE, MASS, ANGLE = 1e4, 1e7, 1e4, 1e4  # m (positions), N and N*m, kg (a link), rad or m (joint values)


@dataclass
class ResultFile:
    """A read result file: where it is, the scenario it names (if any), its frames and, for a run that was
    stopped early, the file's ``interrupted`` entry ({"at_frame", "solved", "reason"})."""

    path: Path | None
    scenario: str | None
    frames: list[Frame]
    interrupted: dict | None = None


class ResultStream:
    """A result file (either format) read frame by frame: iterating it parses one frame at a time, so a long
    motion is never in memory at once; each iteration reads the file again. ``scenario`` and ``interrupted`` are
    known once the frames have been read (the writers put the scenario first, so it is known at once for them)."""

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.scenario: str | None = None
        self.interrupted: dict | None = None
        self.count: int | None = None  # frames, after a whole pass
        self._model: Model | None = None
        self._gravity: list | None = None
        self._last: Frame | None = None  # the compact frame read last (its pose's arrays kept for the next)
        self.compact = is_compact(self.path, ResultFileError)
        for kind, key, _ in self._parts():
            if kind == "frame" or key == "frames":
                break

    def _parts(self, lazy: bool = False) -> Iterator[tuple[str, Any, Any]]:
        """The file's parts (:func:`~solver.io.result.scan.scan`), its top-level entries taken in on the way."""
        for kind, key, value in scan(self.path, ResultFileError, lazy):
            if kind == "key":
                self._entry(key, value)
            yield kind, key, value

    def _entry(self, key: str, value: Any) -> None:
        if key == "scenario":
            self.scenario = value if isinstance(value, str) else None
        elif key == "interrupted":
            self.interrupted = value if isinstance(value, dict) else None
        elif key == "frames":
            raise TableReader(self.path, {}, error=ResultFileError).fail("frames", "a non-empty array of tables", value)
        elif key == "model" and self.compact:
            try:
                self._model = model_from_dict(value)
            except ManikinError as exc:
                raise ResultFileError(f"{self.path}: model: {exc}") from None
        elif key == "gravity" and self.compact:
            self._gravity = value

    def raw(self) -> Iterator[tuple[int, dict]]:
        """(index, raw frame object) of every frame, without building frames (for a quick pass)."""
        yield from self._raw(lazy=False)

    def numbered(self) -> Iterator[tuple[int, Any, Any]]:
        """(index, frame number, raw) of every frame for a quick pass over the numbers: ``raw`` as :meth:`frame`
        takes it, a compact file's frame line not parsed (nor checked) until then, a result JSON's frame not held
        to the nesting limit until then (:class:`~.scan.UncheckedFrame`); the number is the frame's
        ``frame`` (1 when it has none; None for a frame that is not an object or whose ``frame`` is not a number:
        building it says what is wrong)."""
        for index, value in self._raw(lazy=True):
            if isinstance(value, FrameLine):
                yield index, value.number, value
            else:
                yield index, _number(value.data if isinstance(value, UncheckedFrame) else value), value

    def _raw(self, lazy: bool) -> Iterator[tuple[int, Any]]:
        count = 0
        for kind, index, value in self._parts(lazy):
            if kind == "frame" or kind == "line":
                count += 1
                yield index, value
        if not count:
            raise TableReader(self.path, {}, error=ResultFileError).fail("frames", "a non-empty array of tables", [])
        self.count = count

    def frame(self, index: int, raw: Any) -> Frame:
        """The checked frame of a raw frame object (from :meth:`raw` or :meth:`numbered`)."""
        if isinstance(raw, FrameLine):
            raw = parse_line(raw, self.path, ResultFileError)
        elif isinstance(raw, UncheckedFrame):
            raw = checked_frame(raw, self.path, ResultFileError)
        where = f"frames[{index}]."
        if not isinstance(raw, dict):
            raise ResultFileError(f"{self.path}: {where[:-1]}: expected a result frame (an object), got {raw!r:.60}")
        t = TableReader(self.path, raw, where, ResultFileError)
        if not self.compact:
            return _frame(t)
        if self._model is None:
            raise ResultFileError(f"{self.path}: model: expected the manikin's model in the header line (missing)")
        self._last = compact_frame(t, self._model, self._gravity, self._last)
        return self._last

    def __iter__(self) -> Iterator[Frame]:
        for index, raw in self.raw():
            yield self.frame(index, raw)


def _number(raw: Any) -> int | float | None:
    """A raw frame's ``frame`` for the quick pass (1 when absent), None when it is no number."""
    number = raw.get("frame", 1) if isinstance(raw, dict) else None
    return number if isinstance(number, (int, float)) else None


def read_result(path: str | Path) -> ResultFile:
    """Read and check a result file (written by ``python -m solver solve`` or :func:`solver.write_result`, either
    format) with all its frames; :class:`ResultStream` reads a long motion one frame at a time."""
    stream = ResultStream(path)
    frames = list(stream)
    return ResultFile(stream.path, stream.scenario, frames, stream.interrupted)


def result_from_dict(data: Any, path: str | Path = "result") -> ResultFile:
    """The parsed JSON ``data`` of a result file; ``path`` names it in error messages."""
    if not isinstance(data, dict):
        raise ResultFileError(f'{path}: expected a JSON object with a "frames" list, got {type(data).__name__}')
    root = TableReader(path, data, error=ResultFileError)
    frames = [_frame(t) for t in root.table_list("frames", non_empty=True)]
    scenario = data.get("scenario") if isinstance(data.get("scenario"), str) else None
    interrupted = data.get("interrupted") if isinstance(data.get("interrupted"), dict) else None
    return ResultFile(Path(path) if isinstance(path, Path) else None, scenario, frames, interrupted)


def frame_from_dict(raw: Any, where: str = "frame") -> Frame:
    """One result frame (a dict as in the file's ``frames`` list); ``where`` names it in error messages."""
    if not isinstance(raw, dict):
        raise ResultFileError(f"{where}: expected a result frame (an object), got {type(raw).__name__}")
    return _frame(TableReader(where, raw, error=ResultFileError))


def _frame(t: TableReader) -> Frame:
    t.required("joints", "links", "tcps")
    links = _usual_links(t.data["links"]) or _links(t.table_list("links", non_empty=True))
    link_names, link_parent, mass, com = links
    lindex = {n: i for i, n in enumerate(link_names)}
    joints = _usual_joints(t.data["joints"], lindex) or _joints(t.named_tables("joints"), lindex)
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
    return Frame(
        **frame_status(t),
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
    )


def compact_frame(t: TableReader, model: Model, gravity: Any = None, last: Frame | None = None) -> Frame:
    """A frame of the compact format: the model posed by its ``joint_values``, with its contacts and loads;
    ``last``: a frame of the same model read before, whose posed arrays (read, never changed) a frame with its
    joint values takes as they are."""
    values = _vector(t, "joint_values", model.n, ANGLE, "rad or m")
    contacts = []
    for name, c in t.named_tables("contacts").items():
        if name not in model.tcps:
            raise t.fail(f"contacts.{name}", "a contact at one of the TCPs: " + ", ".join(sorted(model.tcps)))
        point, force = _vector(c, "point", 3, LENGTH, "m"), _vector(c, "force", 3, FORCE, "N")
        contacts.append((name, point, force, _vector(c, "moment", 3, FORCE, "N*m", _ZERO)))
    loads = []
    for ld in t.table_list("loads"):
        point, force = _vector(ld, "point", 3, LENGTH, "m"), _vector(ld, "force", 3, FORCE, "N")
        loads.append((ld.choice("tcp", model.tcps, "a TCP name"), point, force))
    g = GRAVITY if gravity is None else TableReader(t.path, {"gravity": gravity}, "", t.error).vector("gravity", 3)
    if last is not None and values.tobytes() == last.joint_value.tobytes():  # the same pose: its arrays shared
        return replace(last, **frame_status(t), contacts=contacts, loads=loads, gravity=np.array(g, dtype=float))
    return frame_of_pose(model, model.forward(values), frame_status(t), contacts, loads, g)


_ZERO = [0.0, 0.0, 0.0]  # a contact's moment when the file gives none (read, never changed)


def _vector(t: TableReader, key: str, size: int, limit: float, unit: str, default: Any = None) -> np.ndarray:
    """``t.vector(key, size, default, limit, unit)``, told at C speed for the usual list of floats within +-limit (a
    compact frame's values); anything else (ints, NaN, a wrong size or type) goes through ``t.vector`` and its
    checks and messages."""
    value = t.data.get(key, default)
    if type(value) is list and len(value) == size:
        if size > 8:  # one pass in C over many values: their types, then their size (NaN fails the comparison)
            if set(map(type, value)) == {float}:
                a = np.array(value, dtype=float)
                if (np.abs(a) <= limit).all():
                    return a
        elif all(type(v) is float and -limit <= v <= limit for v in value):
            return np.array(value, dtype=float)
    return t.vector(key, size, default, limit=limit, unit=unit)


def frame_status(t: TableReader) -> dict:
    """The Frame fields about the solve, from a frame of either format: ``number``, ``converged``, ``unmet``,
    ``broken``."""
    converged = t.get("converged")
    return dict(
        number=t.integer("frame", 1, -1e9, 1e9, "a whole frame number"),
        converged=converged if isinstance(converged, bool) else None,
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


def _floats(values: list, limit: float, size: int | None = None) -> np.ndarray | None:
    """``values`` (floats, or lists of ``size`` floats) as an array when each is a float within +-``limit``; None
    for anything else (an int, a NaN, a wrong size: the checked readers then name it)."""
    if size is not None:
        if not all(type(v) is list and len(v) == size for v in values):
            return None
        values = list(chain.from_iterable(values))
    if not values or set(map(type, values)) != {float}:
        return None
    a = np.array(values, dtype=float)
    return a if (np.abs(a) <= limit).all() else None


def _limits(values: list, unlimited: float, limit: float) -> np.ndarray | None:
    """:meth:`TableReader.limit` of each value (None: ``unlimited``), or None when one is not a float within
    +-``limit`` or null."""
    given = [v for v in values if v is not None]
    if given and _floats(given, limit) is None:
        return None
    return np.array([unlimited if v is None else v for v in values], dtype=float)


def _usual_links(links: Any) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray] | None:
    """:func:`_links` of a frame's links as the writers put them (every name a string, every number a float in
    range), in bulk; None for anything else, which :func:`_links` checks one by one and names."""
    if type(links) is not list or not links or not all(type(lk) is dict for lk in links):
        return None
    names = [lk.get("name") for lk in links]
    if not all(type(n) is str and n for n in names):
        return None
    mass, com = _floats([lk.get("mass") for lk in links], MASS), _floats([lk.get("com") for lk in links], LENGTH, 3)
    if mass is None or com is None or (mass < 0.0).any():
        return None
    index = {n: i for i, n in enumerate(names)}
    parents = [lk.get("parent") for lk in links]
    if not all(p is None or type(p) is str for p in parents):
        return None
    return names, np.array([index.get(p, -1) for p in parents], dtype=int), mass, com.reshape(-1, 3)


def _usual_joints(joints: Any, lindex: dict[str, int]) -> dict[str, Any] | None:
    """:func:`_joints` of a frame's joints as the writers put them, in bulk (each axis normalised as there, one by
    one, for the same bits); None for anything else, which :func:`_joints` checks one by one and names."""
    if type(joints) is not dict or not joints or not all(type(jt) is dict for jt in joints.values()):
        return None
    tables = list(joints.values())
    links = [jt.get("link") for jt in tables]
    if not all(type(link) is str and link in lindex for link in links):
        return None
    values = _floats([jt.get("value") for jt in tables], ANGLE)
    lower = _limits([jt.get("min") for jt in tables], -math.inf, ANGLE)
    upper = _limits([jt.get("max") for jt in tables], math.inf, ANGLE)
    positions = _floats([jt.get("position") for jt in tables], LENGTH, 3)
    axes = _floats([jt.get("axis") for jt in tables], LENGTH, 3)
    strengths = _usual_strengths([jt.get("strength") for jt in tables])
    if values is None or lower is None or upper is None or positions is None or axes is None or strengths is None:
        return None
    axes = axes.reshape(-1, 3)
    norms = [np.linalg.norm(axis) for axis in axes]
    if min(norms) < 1e-9:
        return None
    return dict(
        joint_names=list(joints),
        joint_value=values,
        joint_range=np.column_stack([lower, upper]),
        joint_position=positions.reshape(-1, 3),
        joint_axis=np.array([axis / norm for axis, norm in zip(axes, norms, strict=True)]).reshape(-1, 3),
        prismatic=np.array([jt.get("type") == "prismatic" for jt in tables], dtype=bool),
        joint_link=np.array([lindex[link] for link in links], dtype=int),
        joint_strength=strengths if len(strengths) else None,
    )


def _usual_strengths(values: list) -> np.ndarray | None:
    """:func:`_strength` of each joint as an (n, 2) array (empty when no joint has one), or None for anything but
    null or a pair of floats within +-FORCE or null."""
    if all(v is None for v in values):
        return np.zeros((0, 2))
    if not all(v is None or (type(v) is list and len(v) == 2) for v in values):
        return None
    pairs = _limits([side for v in values if v is not None for side in v], math.inf, FORCE)
    if pairs is None:
        return None
    out = np.full((len(values), 2), math.nan)
    out[[i for i, v in enumerate(values) if v is not None]] = pairs.reshape(-1, 2)
    return out


def _strength(jt: TableReader) -> list[float]:
    """[negative, positive] capacity (N*m), inf where the file says null (unlimited), NaN when not given."""
    value = jt.get("strength")
    if value is None:
        return [math.nan, math.nan]
    if not isinstance(value, list) or len(value) != 2:
        raise jt.fail("strength", "[negative, positive] capacities (numbers or null)", value)
    pair = jt.sub("strength", {"negative": value[0], "positive": value[1]})
    return [pair.limit(side, math.inf, FORCE, "N*m") for side in ("negative", "positive")]
