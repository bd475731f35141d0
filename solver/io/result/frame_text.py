"""JSON text built from arrays through a template: the same characters as ``json.dumps`` of the dicts, cheaper.

A long motion writes the same structure at every frame: the pose part of a result frame repeats its joint names,
limits, types, links and strengths, the links' names, parents and masses, the TCPs' names and links and the
capsules' links and radii (87 KB a frame, most of it not changing). :class:`PoseText` encodes that once per layout
(by ``json.dumps`` itself, each changing value a slot) and each frame only turns its numbers into text: ``repr`` of
a finite float is what ``json.dumps`` writes for it, and ``repr`` of a list of floats is its JSON array. A frame
with a number that is not finite (NaN, inf) goes through the dicts as before.
"""

from __future__ import annotations

import json
from typing import TYPE_CHECKING

import numpy as np

from .document import contacts_dict, frame_status, frame_to_dict, loads_list, rotation_quaternion
from .frame import Frame, ResultFrames

if TYPE_CHECKING:
    from ...body.state import State
    from ...iteration.result import Result

SLOT = "\x00slot"  # a string no name holds: json.dumps writes it as "\u0000slot"
_MARK = json.dumps(SLOT)
COMPACT_JSON = json.JSONEncoder(separators=(",", ":"), check_circular=False)  # made once (dicts here have no loops)


def template(value: object, **dumps) -> tuple[str, int]:
    """``json.dumps(value, **dumps)`` as a %-template: each :data:`SLOT` string a ``%s``, any other ``%`` doubled;
    and the number of slots."""
    text = json.dumps(value, **dumps).replace("%", "%%")
    return text.replace(_MARK, "%s"), text.count(_MARK)


class Numbers:
    """Floats turned into JSON text in bulk (``repr``), remembering whether every one was finite."""

    def __init__(self) -> None:
        self.finite = True

    def _text(self, a: np.ndarray) -> str:
        text = repr(np.asarray(a, dtype=float).tolist())
        self.finite = self.finite and "n" not in text  # "nan", "inf": the only float reprs with an n
        return text

    def items(self, a: np.ndarray) -> list[str]:
        """The text of each number of a vector."""
        return self._text(a)[1:-1].split(", ") if len(a) else []

    def rows(self, a: np.ndarray) -> list[str]:
        """The text inside the brackets of each row of an (n, k) array, k >= 1: ``"x, y, z"``. Each distinct row is
        written once (a body's rows repeat: the joints of a ball joint share a point, a massless link's centre of
        mass is its joint's point); distinct by their bits, so 0.0 and -0.0 stay apart."""
        if not len(a):
            return []
        a = np.ascontiguousarray(a, dtype=float)
        bits = a.view(np.dtype((np.void, a.itemsize * a.shape[1]))).ravel()
        _, first, inverse = np.unique(bits, return_index=True, return_inverse=True)
        texts = self._text(a[first])[2:-2].split("], [")
        return [texts[i] for i in inverse.tolist()]


def interleave(*columns: list[str]) -> list[str]:
    """[a0, b0, c0, a1, b1, c1, ...] of columns [a0, a1, ...], [b0, b1, ...], ... of equal length."""
    out = [""] * sum(len(c) for c in columns)
    for i, column in enumerate(columns):
        out[i :: len(columns)] = column
    return out


def _layout(f: Frame) -> tuple:
    """What the pose template of a frame depends on besides its numbers (equal keys: equal templates)."""
    strength = None if f.joint_strength is None else f.joint_strength.tobytes()
    arrays = (f.joint_range, f.prismatic, f.joint_link, f.link_parent, f.link_mass)
    shapes = tuple((name, float(radius)) for name, _, _, radius in f.collision_shapes)
    tcps = tuple((name, f.tcp_link[name]) for name in f.tcp_position)
    return (tuple(f.joint_names), tuple(f.link_names), strength, shapes, tcps,
            *((a.dtype.str, a.shape, a.tobytes()) for a in arrays))  # fmt: skip


class PoseText:
    """``json.dumps(frame_to_dict(f))`` of frame after frame (default separators), its template kept between frames
    of the same layout, and its text while the pose is held (:meth:`~.frame.Frame.same_pose`)."""

    def __init__(self) -> None:
        self._key: tuple | None = None
        self._template = ""
        self._slots = 0
        self._last: Frame | None = None  # the frame written last and its text
        self._text = ""
        self._frames = ResultFrames()  # result_frame's frames, a held pose's sharing its arrays

    def __call__(self, f: Frame) -> str:
        if f.same_pose(self._last):
            return self._text
        self._last, self._text = f, self._pose(f)
        return self._text

    def _pose(self, f: Frame) -> str:
        key = _layout(f)
        if key != self._key:
            self._template, self._slots = template(frame_to_dict(f, SLOT))
            self._key = key
        names, shapes = list(f.tcp_position), f.collision_shapes
        points = [  # every 3-vector of the pose, written at once (a row repeated is written once)
            f.joint_position, f.joint_axis, f.link_com,
            np.array([f.tcp_position[n] for n in names], dtype=float).reshape(len(names), 3),
            np.array([a for _, a, _, _ in shapes], dtype=float).reshape(len(shapes), 3),
            np.array([b for _, _, b, _ in shapes], dtype=float).reshape(len(shapes), 3),
        ]  # fmt: skip
        numbers = Numbers()
        texts = numbers.rows(np.concatenate(points))
        ends = np.cumsum([len(p) for p in points]).tolist()
        position, axis, com, tcp_position, start, end = (texts[a:b] for a, b in zip([0, *ends[:-1]], ends, strict=True))
        rotation = np.array([rotation_quaternion(f.tcp_rotation[n]) for n in names], dtype=float).reshape(len(names), 4)
        filled = (
            json.dumps(np.asarray(f.gravity, dtype=float).tolist()),
            *interleave(numbers.items(f.joint_value), position, axis),
            *interleave(tcp_position, numbers.rows(rotation)),
            *com,
            json.dumps(contacts_dict(f)),
            json.dumps(loads_list(f)),
            *interleave(start, end),
        )
        if not numbers.finite or len(filled) != self._slots:
            return json.dumps(frame_to_dict(f))  # NaN or inf: written as JSON's NaN, Infinity
        return self._template % filled

    def result_frame(self, result: Result, frame: int = 1, state: State | None = None) -> str:
        """``json.dumps(result_to_dict(result, frame, state))``: the status, then the pose."""
        state = result.state if state is None else state
        status = json.dumps(frame_status(result, frame, state))
        return status[:-1] + ", " + self(self._frames(result, frame, state))[1:]
