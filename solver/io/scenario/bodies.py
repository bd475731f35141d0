"""Manikin bodies: the human (from published anthropometry) and the thesis' snake, built or loaded from TOML.

A body TOML file has one table::

    [body]
    kind = "human"          # or "snake"
    sex = "male"            # human: "male" or "female"
    stature = 1.74          # human: m, 0.5-2.5
    mass = 74.0             # human: kg, 10-300
    percentile = 50         # optional, 0-100
    source = "survey, table, year"   # optional
    # human only, all optional (m): sitting_height, shoulder_breadth, upper_arm_length, forearm_length,
    # hip_breadth, foot_length -- they override the segment lengths they determine (see .measurements)
    # snake only, all optional: segments = 9, segment_length = 0.2 (m), segment_mass = 1.0 (kg)

Presets live in ``presets/manikins/<name>.toml`` at the repository (extension) root.
"""

from __future__ import annotations

from pathlib import Path

from ...body.humans.human import build_human, validate_human
from ...body.humans.measurements import MEASUREMENTS
from ...body.humans.snake import build_snake, validate_snake
from ...body.model import Model
from ...errors import ModelError, is_number
from ...presets import MANIKINS_DIR, PRESETS_DIR, list_presets
from ..files import read_toml
from ..table_reader import TableReader

__all__ = [
    "PRESETS_DIR",
    "MANIKINS_DIR",
    "build_human",
    "build_snake",
    "load_body",
    "load_preset",
    "list_presets",
    "body_from_dict",
]


_COMMON_KEYS = {"kind", "name", "percentile", "source"}
_KEYS = {
    "human": _COMMON_KEYS | {"sex", "stature", "mass"} | set(MEASUREMENTS),
    "snake": _COMMON_KEYS | {"segments", "segment_length", "segment_mass"},
}


def is_body_file(name_or_path: str | Path) -> bool:
    """Whether ``name_or_path`` names a body TOML file (a Path, a ``.toml`` name or a path with a folder)."""
    text = str(name_or_path)
    return isinstance(name_or_path, Path) or text.endswith(".toml") or "/" in text or "\\" in text


def load_preset(name_or_path: str | Path) -> Model:
    """A manikin preset by name (``"male_50"``, see :func:`list_presets`) or a body TOML file by path."""
    if is_body_file(name_or_path):
        return load_body(file=name_or_path)
    return load_body(preset=str(name_or_path))


def load_body(preset: str | None = None, file: str | Path | None = None) -> Model:
    """Build the body of a preset name or of a body TOML file; every problem raises a one-line ModelError."""
    if (preset is None) == (file is None):
        raise ModelError("load_body needs exactly one of preset=<name> or file=<body TOML path>")
    if preset is not None:
        path = MANIKINS_DIR / f"{preset}.toml"
        if not isinstance(preset, str) or preset not in list_presets():
            if isinstance(preset, str) and Path(preset).is_dir():
                raise ModelError(f"{preset}: is a folder, expected a manikin preset name or a body file (TOML)")
            known = ", ".join(list_presets()) or "none"
            raise ModelError(f"unknown manikin preset {preset!r} (known: {known})")
        name = preset
    else:
        path = Path(file)
        if path.is_dir():
            raise ModelError(f"{path}: is a folder, expected a body file (TOML)")
        if not path.is_file():
            raise ModelError(f"body file not found: {path}")
        name = path.stem
    return body_from_dict(read_toml(path, ModelError), where=str(path), name=name)


def body_from_dict(data: dict, where: str = "body", name: str = "body") -> Model:
    """Build a body from parsed TOML ``data`` (a dict with a ``body`` table); ``where`` prefixes error messages."""
    body = data.get("body") if isinstance(data, dict) else None
    if not isinstance(body, dict):
        raise ModelError(f'{where}: missing table [body] (with kind = "human" or "snake")')
    TableReader(where, data, error=ModelError).known({"body"})  # a stray [joints] table must not pass silently
    kind = body.get("kind")
    if kind not in _KEYS:
        raise ModelError(f'{where}: [body] kind must be "human" or "snake", got {kind!r}')
    unknown = sorted(set(body) - _KEYS[kind])
    if unknown:
        raise ModelError(
            f"{where}: [body] unknown key {unknown[0]!r} for kind {kind!r} (known: {', '.join(sorted(_KEYS[kind]))})"
        )
    name = body.get("name", name)
    if not isinstance(name, str) or not name:
        raise ModelError(f"{where}: [body] name must be a non-empty string, got {name!r}")
    info = {"file": where}
    if "source" in body:
        if not isinstance(body["source"], str):
            raise ModelError(f"{where}: [body] source must be a string, got {body['source']!r}")
        info["source"] = body["source"]
    if "percentile" in body:
        p = body["percentile"]
        if not is_number(p) or not 0 <= p <= 100:
            raise ModelError(f"{where}: [body] percentile must be a number in [0, 100], got {p!r}")
        info["percentile"] = p
    try:
        if kind == "human":
            expected = {"sex": "'male' or 'female'", "stature": "a number in m", "mass": "a number in kg"}
            for key, what in expected.items():
                if key not in body:
                    raise ModelError(f"missing key '{key}' (expected {what})")
            validate_human(body["sex"], body["stature"], body["mass"])
            measured = {k: body[k] for k in MEASUREMENTS if k in body}
            return build_human(body["sex"], body["stature"], body["mass"], name=name, info=info, measurements=measured)
        args = (body.get("segments", 9), body.get("segment_length", 0.2), body.get("segment_mass", 1.0))
        validate_snake(*args)
        return build_snake(*args, name=name, info=info)
    except ModelError as exc:
        raise ModelError(f"{where}: [body] {exc}") from None
