"""Objects an operation handles: a shape (an obstacle kind), a mass and named grasps, and grasps proposed from the
shape when a scenario gives none. Units: m, kg; rotations are 3x3 matrices (world = R @ local + origin).

An object's frame: its origin is the middle of its bounds (a box: its centre and axes; other kinds: world axes).
A grasp holds a frame per hand in that frame; the hand's TCP z axis is the palm normal, pointing into the object.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ..collision import Box, Obstacle

PALM_GAP = 0.027  # m: palm outside the face, so the hand's capsule (r 3.3 cm, axis 1.7 cm behind the palm) stays ~1 cm
GRIP_HEIGHT = 0.25  # of its height above the object's centre: where proposed side grasps are (its upper half)
AUTO_BOTH_MASS = 3.0  # kg: heavier objects are taken with both hands when the operation says no hand
AUTO_BOTH_WIDTH = 0.30  # m: so are objects wider than this
WIDEST_GRIP = 0.6  # m: a box wider than this across x (and deeper than wide) is gripped on its front and back
HAND_LOCK = ("x", "y", "z", "rx", "ry")  # a given grasp's default: the palm free to turn about its normal
PROPOSED_LOCK = ("x", "y", "z", "rx", "ry", "rz")  # a proposed side grasp holds the fingers' direction too (below)
# a hand TCP's axes (male_50: TCP x along the fingers, z the palm normal) on a side face, palm normal towards the
# body's middle and the fingers pointing forward (-y, away from the body): a hand with its fingers hanging down
# reaches 9 cm below the grip and meets the table or pallet the object rests on (the first slice's 6/36 frames)
SIDE_R = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])  # hand_r: palm normal along +x
SIDE_L = np.array([[0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])  # hand_l: palm normal along -x


@dataclass(frozen=True)
class HandFrame:
    """One hand's frame in a grasp: ``position`` (3,) m and ``rotation`` (3, 3) in the object's frame; ``lock``."""

    position: np.ndarray
    rotation: np.ndarray
    lock: tuple[str, ...] = HAND_LOCK


@dataclass(frozen=True)
class Grasp:
    """A named grasp: a frame per hand TCP (one or two hands); ``proposed``: made from the geometry."""

    name: str
    hands: dict[str, HandFrame]
    proposed: bool = False


@dataclass(frozen=True)
class WorkObject:
    """An object: ``shape`` where it rests at first, ``mass`` kg, ``grasps`` by name, ``mating`` (3,) m in its frame
    where a placed object's bottom middle goes (None: its top middle)."""

    name: str
    shape: Obstacle
    mass: float
    grasps: dict[str, Grasp] = field(default_factory=dict)
    mating: np.ndarray | None = None

    @property
    def rotation(self) -> np.ndarray:
        return np.asarray(self.shape.rotation) if isinstance(self.shape, Box) else np.eye(3)

    @property
    def size(self) -> np.ndarray:
        """Edge lengths (3,) m along the object's axes (its bounds for a kind other than a box)."""
        if isinstance(self.shape, Box):
            return np.asarray(self.shape.size, dtype=float)
        low, high = self.shape.bounds()
        return high - low


def origin_of(shape: Obstacle) -> np.ndarray:
    """The middle of ``shape``'s bounds (3,) m: the object frame's origin."""
    if isinstance(shape, Box):
        return np.asarray(shape.center, dtype=float)
    low, high = shape.bounds()
    return (low + high) / 2.0


def moved(shape: Obstacle, shift: np.ndarray) -> Obstacle:
    """``shape`` translated by ``shift`` (3,) m (every point-valued key moved; the kind checks itself again)."""
    changes = {}
    for key, what in shape.keys.items():
        if what in ("point", "points"):
            changes[key] = np.asarray(getattr(shape, key)) + shift
    return dataclasses.replace(shape, **changes)


def world_hand(origin: np.ndarray, rotation: np.ndarray, hand: HandFrame) -> tuple[np.ndarray, np.ndarray]:
    """A grasp hand's world (position, rotation) with the object at ``origin``, ``rotation``."""
    return origin + rotation @ hand.position, rotation @ hand.rotation


def propose_grasps(obj: WorkObject, hands: tuple[str, ...] = ("hand_r", "hand_l")) -> dict[str, Grasp]:
    """Grasps made from the geometry: both hands on opposite side faces (its left and right faces, x, unless it
    is wider than :data:`WIDEST_GRIP` and deeper than wide: then front and back), and each hand alone on its face.
    Each palm :data:`PALM_GAP` m outside the face, at mid height."""
    half = obj.size / 2.0
    across = 0 if obj.size[0] <= WIDEST_GRIP or half[0] <= half[1] else 1  # left and right faces, unless too wide
    out = {}
    frames = {}
    for tcp, sign, base in (("hand_r", -1.0, SIDE_R), ("hand_l", 1.0, SIDE_L)):
        position = np.zeros(3)
        position[across] = sign * (half[across] + PALM_GAP)
        position[2] = GRIP_HEIGHT * obj.size[2]
        turn = np.eye(3) if across == 0 else np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
        frames[tcp] = HandFrame(position, turn @ base, PROPOSED_LOCK)  # across y: the side frames turned 90 deg about z
    both = tuple(h for h in ("hand_r", "hand_l") if h in hands)
    if len(both) == 2:
        out["both sides"] = Grasp("both sides", {h: frames[h] for h in both}, proposed=True)
    for h in both:
        out[f"{h} side"] = Grasp(f"{h} side", {h: frames[h]}, proposed=True)
    return out


def grasp_for(obj: WorkObject, name: str | None, hands: str) -> Grasp | None:
    """The grasp ``name``, else the first with the hands ``hands`` ("both", "right", "left", "auto"); None: none."""
    if name is not None:
        return obj.grasps.get(name)
    fallback = None
    if hands == "auto":  # two hands for a heavy or wide object, as a person would (else whatever grasp it has)
        fallback = next(iter(obj.grasps.values()), None)
        hands = "both" if obj.mass > AUTO_BOTH_MASS or float(np.max(obj.size[:2])) > AUTO_BOTH_WIDTH else "right"
    wanted = {"both": 2, "right": ("hand_r",), "left": ("hand_l",)}.get(hands)
    for grasp in obj.grasps.values():
        tcps = tuple(grasp.hands)
        if wanted is None or wanted == len(tcps) or wanted == tcps:
            return grasp
    return fallback
