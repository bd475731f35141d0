"""The snake test body of the thesis (Delfs 2012, section 6.2): a chain of segments on a base plate.

Each segment turns up to 90 degrees about x, y and z at its lower end; a ``floor`` TCP with a square sole lets the
base slide on the floor and a ``top`` TCP sits on the last segment's upper end. Units: m, kg, rad, N*m.
"""

from __future__ import annotations

import math

import numpy as np

from ...errors import ModelError, is_number
from ..builder import ModelBuilder
from ..model import Model

BASE_MASS = 0.5  # kg, estimate
BASE_COM = (0.0, 0.0, 0.02)  # m, estimate
BASE_HEIGHT = 0.04  # m: seg1's joints sit this high on the base
FLOOR_HALF_SIDE = 0.1  # m: the floor TCP's square sole is +-0.1 m
SEGMENT_LIMIT = math.radians(90.0)
SEGMENT_STRENGTH = 100.0  # N*m per joint and direction, estimate
MAX_LENGTH, MAX_MASS = 10.0, 1000.0  # m, kg per segment: the bounds of a body file's values


def validate_snake(segments: int, segment_length: float, segment_mass: float) -> None:
    """Raise ModelError unless segments is an int in [1, 100], length in (0, 10] m and mass in (0, 1000] kg."""
    if isinstance(segments, bool) or not isinstance(segments, int) or not 1 <= segments <= 100:
        raise ModelError(f"segments must be an integer in [1, 100], got {segments!r}")
    for key, value, high, unit in (("segment_length", segment_length, MAX_LENGTH, "m"),
                                   ("segment_mass", segment_mass, MAX_MASS, "kg")):  # fmt: skip
        if not is_number(value) or not 0 < value <= high:
            raise ModelError(f"{key} must be a number in (0, {high:g}] {unit}, got {value!r}")


def build_snake(
    segments: int = 9,
    segment_length: float = 0.2,
    segment_mass: float = 1.0,
    name: str = "snake",
    *,
    info: dict | None = None,
) -> Model:
    """Snake of ``segments`` segments, each ``segment_length`` m long with ``segment_mass`` kg at its middle."""
    validate_snake(segments, segment_length, segment_mass)
    length = float(segment_length)
    body_info = dict(
        kind="snake",
        segments=segments,
        segment_length=length,
        segment_mass=float(segment_mass),
        mass=BASE_MASS + segments * float(segment_mass),
        source="Delfs 2012 thesis, section 6.2",
    )
    body_info.update(info or {})
    b = ModelBuilder(name, body_info)
    parent = b.add_exterior_root((0.0, 0.0, 0.0), link="base")
    b.set_mass("base", BASE_MASS, BASE_COM)
    origin = (0.0, 0.0, BASE_HEIGHT)
    for i in range(1, segments + 1):
        for axis_name, axis in (("rx", (1.0, 0.0, 0.0)), ("ry", (0.0, 1.0, 0.0)), ("rz", (0.0, 0.0, 1.0))):
            last = axis_name == "rz"
            parent = b.add_joint(
                f"seg{i}_{axis_name}",
                parent,
                axis,
                origin,
                limits=(-SEGMENT_LIMIT, SEGMENT_LIMIT),
                strength=(SEGMENT_STRENGTH, SEGMENT_STRENGTH),
                link=f"seg{i}" if last else None,
                mass=float(segment_mass) if last else 0.0,
                com=(0.0, 0.0, 0.5 * length) if last else (0.0, 0.0, 0.0),
            )
            origin = (0.0, 0.0, 0.0)
        origin = (0.0, 0.0, length)
    h = FLOOR_HALF_SIDE
    b.add_tcp("floor", "base", (0.0, 0.0, 0.0), sole=np.array([[-h, -h], [h, -h], [h, h], [-h, h]]))
    b.add_tcp("top", f"seg{segments}", (0.0, 0.0, length))
    return b.build()
