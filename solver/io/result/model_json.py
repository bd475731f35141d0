"""Model <-> plain JSON values: the arrays of a :class:`~solver.body.model.Model`, so a compact result file carries its
manikin once and a reader recomputes every frame's world positions from the joint values alone.

Non-finite numbers (unlimited joint ranges, unknown strengths) are written as the strings "inf", "-inf", "nan",
so the file stays standard JSON. Units as in the model: m, rad, kg, N*m.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ...body.model import Model, Tcp
from ...errors import ModelError

ARRAYS = ("parent", "prismatic", "axis", "origin_rotation", "origin_position", "lower", "upper", "neutral",
          "strength", "range_weight", "mass", "com")  # fmt: skip
_SPECIAL = {"inf": math.inf, "-inf": -math.inf, "nan": math.nan}


def _plain(value: Any) -> Any:
    """Nested lists of numbers with non-finite floats as strings."""
    if isinstance(value, list):
        return [_plain(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    return value


def _array(value: Any, dtype: type = float) -> np.ndarray:
    """The array of nested lists written by :func:`_plain`."""

    def number(v: Any) -> Any:
        if isinstance(v, list):
            return [number(u) for u in v]
        if isinstance(v, str):
            return _SPECIAL[v]
        return v

    return np.asarray(number(value), dtype=dtype)


def model_to_dict(model: Model) -> dict:
    """The model as JSON values: name, joint and link names, every array, the TCP frames."""
    data: dict[str, Any] = dict(name=model.name, joint_names=list(model.joint_names), link_names=list(model.link_names))
    for name in ARRAYS:
        data[name] = _plain(np.asarray(getattr(model, name)).tolist())
    data["tcps"] = {
        name: dict(link=int(t.link), rotation=np.asarray(t.rotation, float).tolist(),
                   position=np.asarray(t.position, float).tolist(),
                   sole=None if t.sole is None else np.asarray(t.sole, float).tolist())
        for name, t in model.tcps.items()
    }  # fmt: skip
    return data


def model_from_dict(data: dict) -> Model:
    """The model of :func:`model_to_dict`; malformed data raises ModelError (one line)."""
    try:
        arrays = {name: _array(data[name]) for name in ARRAYS}
        arrays["parent"] = arrays["parent"].astype(int)
        arrays["prismatic"] = arrays["prismatic"].astype(bool)
        tcps = {
            name: Tcp(name, int(t["link"]), _array(t["rotation"]), _array(t["position"]),
                      None if t.get("sole") is None else _array(t["sole"]))
            for name, t in data["tcps"].items()
        }  # fmt: skip
        n = len(data["joint_names"])
        shapes = dict(axis=(n, 3), origin_rotation=(n, 3, 3), origin_position=(n, 3), strength=(n, 2), com=(n, 3))
        for name, array in arrays.items():
            if array.shape != shapes.get(name, (n,)):
                raise ValueError(f"{name} has shape {array.shape}, expected {shapes.get(name, (n,))}")
        return Model(str(data["name"]), tuple(data["joint_names"]), tuple(data["link_names"]), tcps=tcps, **arrays)
    except (KeyError, TypeError, ValueError, AttributeError, IndexError) as exc:
        raise ModelError(f"not a model description ({type(exc).__name__}: {exc})") from None
