"""The shipped body-mesh data (``presets/body_mesh/``): the MakeHuman / MPFB 2 base mesh, its macro targets, the
default rig's skin weights and the rigs' bone tables, loaded into arrays. NumPy only (a real Blender runs it).

Points are the mesh's vertices followed by *anchors* (joint-cube centres and a few helper vertices the rigs name):
targets, weights and rig bone ends all index this one list. Units: metres, Blender axes (z up, the body faces -y,
its left side is +x). ``blender_manikin.dev.prepare_body_mesh`` writes the files.
"""

from __future__ import annotations

import json
import zipfile
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..errors import ModelError
from ..presets import PRESETS_DIR

BODY_MESH_DIR = PRESETS_DIR / "body_mesh"
MESH_FILE = "mpfb2_base.npz"
RIGS_FILE = "mpfb2_rigs.json"
KEYS = ("vertices", "faces", "anchor_names", "anchors", "weight_bones", "weight_offsets", "weight_bone",
        "weight_value", "eye_radius", "target_names", "target_use", "delta_offsets", "delta_index", "delta_value",
        "delta_scale")  # fmt: skip
REGENERATE = "python -m blender_manikin.dev.prepare_body_mesh"


@dataclass(frozen=True, eq=False)
class BodyData:
    """The base mesh and what shapes and skins it (see the module docstring for the point list)."""

    vertices: np.ndarray  # (N, 3) m, the base mesh (MakeHuman's neutral adult)
    faces: np.ndarray  # (F, 4) int, quads, counter-clockwise seen from outside
    anchor_names: tuple[str, ...]
    anchors: np.ndarray  # (A, 3) m
    weight_bones: tuple[str, ...]  # the MPFB default rig's bones, sorted
    weights: np.ndarray  # (N + A, B) skin weights of every point over ``weight_bones``, rows summing to 1
    targets: dict[str, tuple[np.ndarray, np.ndarray]]  # name -> (point indices, deltas (k, 3) m)
    rigs: dict  # rig name -> {"scale_factor", "bones": {name: {"parent", "roll", "head", "tail", ...}}}
    eye_radius: float  # m, of the eyeballs the mesh leaves out

    @property
    def points(self) -> np.ndarray:
        """(N + A, 3) m: the vertices, then the anchors."""
        return np.concatenate([self.vertices, self.anchors])

    def anchor(self, name: str) -> int:
        """Point index of anchor ``name`` (e.g. ``joint-l-elbow``)."""
        try:
            return len(self.vertices) + self.anchor_names.index(name)
        except ValueError:
            raise ModelError(f"{MESH_FILE}: no anchor '{name}'") from None


def _arrays(path: Path) -> dict[str, np.ndarray]:
    try:
        with np.load(path, allow_pickle=False) as npz:
            missing = [k for k in KEYS if k not in npz.files]
            if missing:
                raise ModelError(f"{path}: key '{missing[0]}' missing (regenerate it: {REGENERATE})")
            return {k: npz[k] for k in KEYS}
    except FileNotFoundError:
        raise ModelError(f"{path}: body mesh data not found (regenerate it: {REGENERATE})") from None
    except (OSError, ValueError, zipfile.BadZipFile) as exc:
        raise ModelError(f"{path}: not a body mesh data file ({exc})") from None


def _targets(a: dict[str, np.ndarray]) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Decode the deduplicated int16 deltas: stored target k is rows offsets[k]:offsets[k+1] times scale[k]."""
    offsets, unique = a["delta_offsets"], []
    for k, step in enumerate(a["delta_scale"]):
        rows = slice(int(offsets[k]), int(offsets[k + 1]))
        unique.append((a["delta_index"][rows].astype(np.intp), a["delta_value"][rows].astype(float) * float(step)))
    return {str(name): unique[int(k)] for name, k in zip(a["target_names"], a["target_use"], strict=True)}


def _weights(a: dict[str, np.ndarray], n_points: int) -> np.ndarray:
    offsets = a["weight_offsets"].astype(np.intp)
    if len(offsets) != n_points + 1:
        raise ModelError(f"{MESH_FILE}: weight_offsets: expected {n_points + 1} entries, got {len(offsets)}")
    rows = np.repeat(np.arange(n_points), np.diff(offsets))
    dense = np.zeros((n_points, len(a["weight_bones"])))
    dense[rows, a["weight_bone"].astype(np.intp)] = a["weight_value"]
    return dense


def _rigs(path: Path) -> dict:
    try:
        rigs = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ModelError(f"{path}: rig tables not found (regenerate them: {REGENERATE})") from None
    except (OSError, ValueError) as exc:
        raise ModelError(f"{path}: not a rig table file ({exc})") from None
    if "default" not in rigs:
        raise ModelError(f"{path}: key 'default' missing (the MPFB default rig)")
    return rigs


@lru_cache(maxsize=2)
def load_body_data(folder: Path = BODY_MESH_DIR) -> BodyData:
    """The body-mesh data in ``folder`` (default: the shipped ``presets/body_mesh``), read once."""
    folder = Path(folder)
    a = _arrays(folder / MESH_FILE)
    n_points = len(a["vertices"]) + len(a["anchors"])
    return BodyData(
        vertices=a["vertices"].astype(float),
        faces=a["faces"].astype(np.intp),
        anchor_names=tuple(str(n) for n in a["anchor_names"]),
        anchors=a["anchors"].astype(float),
        weight_bones=tuple(str(n) for n in a["weight_bones"]),
        weights=_weights(a, n_points),
        targets=_targets(a),
        rigs=_rigs(folder / RIGS_FILE),
        eye_radius=float(a["eye_radius"]),
    )


def bone_end(point: dict, points: np.ndarray) -> np.ndarray:
    """A rig table's bone end (``{"mean": [...]}`` or ``{"xyz": [i, j, k]}``) on ``points`` (m)."""
    if "xyz" in point:
        return np.array([points[i, k] for k, i in enumerate(point["xyz"])])
    return points[point["mean"]].mean(axis=0)


def rig_rest(data: BodyData, rig: str, points: np.ndarray) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Bone name -> (head, tail) of rig ``rig`` (e.g. ``mixamo``) on ``points`` (m), e.g. a shaped or fitted body."""
    try:
        bones = data.rigs[rig]["bones"]
    except KeyError:
        raise ModelError(f"{RIGS_FILE}: no rig '{rig}' (known: {', '.join(sorted(data.rigs))})") from None
    return {name: (bone_end(b["head"], points), bone_end(b["tail"], points)) for name, b in bones.items()}
