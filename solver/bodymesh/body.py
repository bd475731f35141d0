"""A manikin's skinned body: the MPFB base mesh shaped to its sex, stature and mass, fitted onto its joints and
weighted to its bones. NumPy only.

1. Macros (:mod:`.macros`): gender from the body's sex; height so the shaped mesh is as tall as the body's
   stature; weight so the *fitted* mesh's volume at :data:`~.measure.BODY_DENSITY` is the body's mass, clipped
   to MakeHuman's range (its heaviest average-muscle bodies hold about BMI 22 (female) and 23 (male) at water
   density, so our BMI-24 presets get weight 1 and a mesh 3-11 % lighter than the manikin: ``FittedBody.mass``).
   Muscle stays at MakeHuman's average (raising it for the missing mass makes a body builder of the 5th
   percentile woman), proportions neutral, age at 25 years.
2. Fit (:mod:`.fit`): segment affines blended by smoothed MPFB weights move the shaped points into our zero pose.
3. Weights (:mod:`.transfer`): the MPFB weights carried over to our bones.

The fit error of each landmark (:mod:`.landmarks`) is the distance (m) from the fitted MPFB joint (its joint cube's
centre, carried along by the skin weights) to our joint centre.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from ..body.model import Model
from .data import BodyData, load_body_data, rig_rest
from .fit import blend, segment_affines, segment_weights
from .landmarks import SIDES, mpfb_landmarks, our_joint_names, our_landmarks
from .macros import Macros, shape
from .measure import mass, smooth, stature
from .transfer import transfer

FIT_SMOOTHING = 16  # rounds of neighbour averaging of the fit's weights (a few cm on this mesh)
SEX_GENDER = {"female": 0.0, "male": 1.0}


@dataclass(frozen=True, eq=False)
class FittedBody:
    """The skinned body in our zero pose (m, world; the armature's rest pose)."""

    vertices: np.ndarray  # (N, 3)
    faces: np.ndarray  # (F, 4) quads
    points: np.ndarray  # (N + A, 3): the vertices, then the anchors (joint cubes), fitted alike
    macros: Macros
    bone_names: tuple[str, ...]  # our armature's bones (link names)
    weights: np.ndarray  # (N, B) over bone_names, rows summing to 1
    fit_error: dict[str, float]  # landmark -> distance (m) of the fitted MPFB joint from ours
    joint_names: dict[str, str]  # landmark -> our joint at it
    mass: float  # kg: the mesh's volume at BODY_DENSITY
    cross_side_removed: float  # largest share of a vertex's weight dropped for being on the other side's bone
    eye_centres: np.ndarray  # (2, 3) left, right (m): where to put eyeballs (the mesh has sockets, no eyes)
    eye_radius: float  # m
    data: BodyData

    def rig(self, name: str) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Bone -> (head, tail) (m) of a shipped rig (``default``, ``game_engine``, ``mixamo``, ``cmu_mb``,
        ``rigify_human``) placed on this body."""
        return rig_rest(self.data, name, self.points)


@lru_cache(maxsize=2)
def _fit_weights(data: BodyData) -> tuple[list[str], np.ndarray]:
    keys, weights = segment_weights(data)
    n = len(data.vertices)
    weights[:n] = smooth(weights[:n], data.faces, FIT_SMOOTHING)
    return keys, weights


def fit_points(data: BodyData, model: Model, macros: Macros) -> np.ndarray:
    """(N + A, 3) m: the mesh shaped by ``macros`` and fitted onto ``model``'s zero-pose joints."""
    points = shape(data, macros)
    n = len(data.vertices)
    mp = mpfb_landmarks(data, points)
    mp["pelvis_centre"] = points[data.anchor("joint-pelvis")]
    mp["floor"] = float(points[:n, 2].min())
    keys, weights = _fit_weights(data)
    hips = points[:n][(weights[:n, [keys.index(k) for k in ("pelvis", "thigh_l", "thigh_r")]].sum(axis=1) > 0.5)
                      & (np.abs(points[:n, 2] - mp["hip_l"][2]) < 0.02)]  # fmt: skip
    mp["hip_breadth"] = float(np.ptp(hips[:, 0]))
    feet = {}
    for s in SIDES:
        on_foot = points[:n][weights[:n, keys.index(f"foot_{s}")] > 0.5]
        feet[s] = float(np.ptp(on_foot[:, 1]))
    affines = segment_affines(mp, our_landmarks(model), float(points[:n, 2].max()), feet)
    return blend(points, keys, weights, affines)


def _height_for(data: BodyData, macros: Macros, target: float) -> float:
    """The height macro giving the shaped mesh ``target`` stature (m): linear within each half of its range."""
    n = len(data.vertices)

    def tall(h: float) -> float:
        return stature(shape(data, replace(macros, height=h))[:n])

    return _interpolate([0.0, 0.5, 1.0], [tall(0.0), tall(0.5), tall(1.0)], target)


def _interpolate(xs: list[float], ys: list[float], target: float) -> float:
    """x in [min xs, max xs] where the piecewise-linear, monotonic ys(x) reaches ``target``, clipped."""
    order = np.argsort(ys)
    return float(np.clip(np.interp(target, np.asarray(ys)[order], np.asarray(xs)[order]), min(xs), max(xs)))


def _mass_level(data: BodyData, model: Model, macros: Macros, name: str, levels: list[float]) -> float:
    """The value of macro ``name`` within ``levels`` giving the fitted mesh the model's mass: the fitted mass at
    each level, interpolated."""
    n = len(data.vertices)
    masses = [mass(fit_points(data, model, replace(macros, **{name: v}))[:n], data.faces) for v in levels]
    return _interpolate(levels, masses, model.total_mass)


def calibrate(data: BodyData, model: Model) -> Macros:
    """Macros for ``model``: gender from its sex, height from its stature, weight from its mass (see above)."""
    target = float(our_landmarks(model)["stature"][2])
    macros = Macros(gender=SEX_GENDER.get(str(model.info.get("sex", "")), 0.5))
    for _ in range(2):  # the weight targets change stature a little: settle height and weight twice
        macros = replace(macros, height=_height_for(data, macros, target))
        macros = replace(macros, weight=_mass_level(data, model, macros, "weight", [0.0, 0.5, 1.0]))
    return macros


def fit_body(model: Model, data: BodyData | None = None, macros: Macros | None = None) -> FittedBody:
    """The skinned body of a human ``model`` (macros calibrated unless given); ModelError for a non-human."""
    data = load_body_data() if data is None else data
    macros = calibrate(data, model) if macros is None else macros
    points = fit_points(data, model, macros)
    n = len(data.vertices)
    vertices = points[:n]
    ours = our_landmarks(model)
    fitted = mpfb_landmarks(data, points)
    errors = {k: float(np.linalg.norm(fitted[k] - ours[k])) for k in fitted}
    names, weights, removed = transfer(model, data.weight_bones, data.weights[:n], vertices, data.vertices[:, 0])
    base_eyes = data.points[[data.anchor("joint-l-eye"), data.anchor("joint-r-eye")]]
    eyes = points[[data.anchor("joint-l-eye"), data.anchor("joint-r-eye")]]
    eye_scale = np.linalg.norm(eyes[0] - eyes[1]) / np.linalg.norm(base_eyes[0] - base_eyes[1])
    return FittedBody(
        vertices=vertices, faces=data.faces, points=points, macros=macros, bone_names=tuple(names), weights=weights,
        fit_error=errors, joint_names=our_joint_names(), mass=mass(vertices, data.faces), cross_side_removed=removed,
        eye_centres=eyes, eye_radius=float(data.eye_radius * eye_scale), data=data,
    )  # fmt: skip


def forget_loaded() -> None:
    """Drop the body-mesh data and fit weights kept after the first fit (~30 MB): for a process that has built its
    manikins' skins and goes on with other work (a long headless bake); the next fit reads them again (~0.2 s)."""
    _fit_weights.cache_clear()
    load_body_data.cache_clear()
