"""A manikin's skinned body: the MPFB base mesh shaped to its sex, stature and mass, fitted onto its joints and
weighted to its bones. NumPy only.

1. Macros (:mod:`.macros`): gender from the body's sex; height so the shaped mesh is as tall as the body's
   stature; weight so the *fitted* mesh's volume at :data:`~.measure.BODY_DENSITY` is the body's mass (clipped to
   MakeHuman's range); muscle stays at MakeHuman's average, proportions neutral, age 25.
2. Fit (:mod:`.fit`): segment affines blended by smoothed MPFB weights move the shaped points into our zero pose.
3. Weights (:mod:`.transfer`): the MPFB weights carried over to our bones.

The fit error of each landmark (:mod:`.landmarks`) is the distance (m) from the fitted MPFB joint (its joint cube's
centre, carried along by the skin weights) to our joint centre.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..model import Model
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
        return stature(shape(data, Macros(macros.gender, macros.muscle, macros.weight, h))[:n])

    return _interpolate([0.0, 0.5, 1.0], [tall(0.0), tall(0.5), tall(1.0)], target)


def _interpolate(xs: list[float], ys: list[float], target: float) -> float:
    """x in [xs[0], xs[-1]] where the piecewise-linear ys(x) (increasing) reaches ``target``, clipped."""
    return float(np.clip(np.interp(target, ys, xs), xs[0], xs[-1]))


def calibrate(data: BodyData, model: Model) -> Macros:
    """Macros for ``model``: gender from its sex, height from its stature, weight from its mass (see above)."""
    gender = SEX_GENDER.get(str(model.info.get("sex", "")), 0.5)
    target = float(our_landmarks(model)["stature"][2])
    macros = Macros(gender=gender)
    for _ in range(2):  # the weight targets change stature a little: settle height and weight twice
        macros = Macros(gender, macros.muscle, macros.weight, _height_for(data, macros, target))
        levels = [0.0, 0.5, 1.0]
        masses = [mass(fit_points(data, model, Macros(gender, macros.muscle, w, macros.height))[: len(data.vertices)],
                       data.faces) for w in levels]  # fmt: skip
        macros = Macros(gender, macros.muscle, _interpolate(levels, masses, model.total_mass), macros.height)
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
