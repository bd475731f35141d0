"""A pose of ours onto another skeleton: rest poses aligned, the hips carrying the translation, limbs pinned by
two-bone IK. NumPy only; world space, m.

Every mapped target bone turns in the world as its source bone does from its rest: ``R_t = R_s R_s0^T R_t0``
(``target_pose_world = source_pose_world source_rest_world^-1 target_rest_world`` for the rotation), so the two
rest poses need not agree (their A-pose or T-pose arms, their bone rolls). Heads follow the target's own chain.
Positions scale by the leg-length ratio about each skeleton's *origin*, the midpoint of its ankles at rest:
``P(p) = o_t + ratio Y (p - o_s)``, where ``Y`` turns our facing onto the target's about world up
(:mod:`.facing`; world turns are conjugated alike, ``Y R Y^T``). The target's hips sit where our pelvis carries
them: the scaled pelvis head plus the hips' rest offset from it, turned with the pelvis. A pinned foot's ankle goes
to its scaled ankle plus its rest offset, turned with the foot (a support stays put); a pinned hand's wrist goes to
the scaled wrist (``body`` goals: where the hand is in the scaled scene) or (``arm`` goals) to the target's
shoulder plus our shoulder-to-wrist vector scaled by the arm-length ratio, always within the arm's reach
(:func:`solve_motion` picks one per motion). Unmapped target bones keep their rest pose relative to their parent.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from .facing import facing_turn
from .skeleton import Skeleton, rigid_inverse, rotation_between
from .two_bone import two_bone_ik

# The two-bone limbs, named after their end bone: (upper, lower, end) of ours.
LIMBS = {
    "foot_l": ("thigh_l", "shank_l", "foot_l"),
    "foot_r": ("thigh_r", "shank_r", "foot_r"),
    "hand_l": ("upper_arm_l", "forearm_l", "hand_l"),
    "hand_r": ("upper_arm_r", "forearm_r", "hand_r"),
}
HIPS = "pelvis"  # our bone carrying the body's translation
# Bones whose rest direction is aligned with ours (arms in a T- or A-pose, fingers straight or curled), each with
# the bones of ours whose head ends its segment, first mapped one counts; without one, the parent's alignment.
ALIGNED = {
    **{f"upper_arm_{s}": (f"forearm_{s}",) for s in "lr"},
    **{f"forearm_{s}": (f"hand_{s}",) for s in "lr"},
    **{f"hand_{s}": tuple(f"{f}_{s}_proximal" for f in ("middle", "ring", "index", "little")) for s in "lr"},
    **{
        f"{f}_{s}_{a}": (f"{f}_{s}_{b}",)
        for s in "lr"
        for f in ("index", "middle", "ring", "little", "thumb")
        for a, b in (("metacarpal", "proximal"), ("proximal", "middle"), ("middle", "distal"), ("proximal", "distal"))
    },
    **{f"{f}_{s}_distal": () for s in "lr" for f in ("index", "middle", "ring", "little", "thumb")},
}
FORWARD = np.array([0.0, -1.0, 0.0])  # our manikin faces -y in its armature's space
HAND_GOALS = ("auto", "body", "arm")  # auto: body goals when every one is in reach, else arm goals
REACH_M = 1e-3  # m: a pinned end this close to its goal reached it


@dataclass(frozen=True, eq=False)
class Plan:
    """Everything about a source-target pair that does not change from frame to frame."""

    source: Skeleton  # our armature at rest (world)
    target: Skeleton
    pairs: dict[int, int]  # target bone -> source bone
    hips: tuple[int, int]  # (our pelvis, their hips bone)
    ratio: float  # target leg length / ours
    source_origin: np.ndarray  # (3,) m: midpoint of our ankles at rest
    target_origin: np.ndarray
    forward: np.ndarray  # (3,) the target's rest forward direction in the world (ours turned by ``turn``)
    turn: np.ndarray  # (3, 3) about world up: our facing onto the target's
    facing_deg: float  # its angle (degrees)
    arm_ratios: dict[str, float]  # hand_l/hand_r -> the target's arm length (shoulder-elbow-wrist) / ours
    aligned_rest: dict[int, np.ndarray]  # target bone -> its rest rotation (3x3, world) turned to match ours
    keyed: tuple[int, ...]  # target bones to key: the mapped ones and their ancestors, parents first

    def scaled(self, p: np.ndarray) -> np.ndarray:
        """A point of ours (m, world) where the target's proportions put it."""
        return self.target_origin + self.ratio * self.turn @ (np.asarray(p, dtype=float) - self.source_origin)


def _leg(skel: Skeleton, names: tuple[str, str, str]) -> float:
    heads = [skel.heads[skel.index(n)] for n in names]
    return float(np.linalg.norm(heads[1] - heads[0]) + np.linalg.norm(heads[2] - heads[1]))


def plan(source: Skeleton, target: Skeleton, bone_map: dict[str, str], source_world_rotation: np.ndarray) -> Plan:
    """The plan for ``bone_map`` (our bone -> their bone; every limb bone and the pelvis mapped, see
    :func:`.bone_map.check_map`); ``source_world_rotation`` (3x3) turns our armature's axes into the world's."""
    pairs = {target.index(theirs): source.index(ours) for ours, theirs in bone_map.items()}
    if len(pairs) != len(bone_map):
        raise ModelError("bone map: a target bone is mapped twice")
    legs = {}
    for side in "lr":
        ours = LIMBS[f"foot_{side}"]
        legs[side] = (_leg(source, ours), _leg(target, tuple(bone_map[n] for n in ours)))
    ratio = sum(t for _, t in legs.values()) / sum(s for s, _ in legs.values())
    arms = {f"hand_{s}": _leg(target, tuple(bone_map[n] for n in LIMBS[f"hand_{s}"])) /
            _leg(source, LIMBS[f"hand_{s}"]) for s in "lr"}  # fmt: skip
    facing, facing_deg = facing_turn(source, target, bone_map)
    ankles = [(source.index(f"foot_{s}"), target.index(bone_map[f"foot_{s}"])) for s in "lr"]
    keyed: set[int] = set()
    for t in pairs:
        keyed.update([t, *target.ancestors(t)])
    turns = _alignment(source, target, bone_map, facing)
    aligned_rest = {t: turns.get(source.names[s], np.eye(3)) @ target.rest[t, :3, :3] for t, s in pairs.items()}
    return Plan(
        source=source, target=target, pairs=pairs, hips=(source.index(HIPS), target.index(bone_map[HIPS])),
        ratio=ratio, source_origin=np.mean([source.heads[s] for s, _ in ankles], axis=0),
        target_origin=np.mean([target.heads[t] for _, t in ankles], axis=0),
        forward=facing @ np.asarray(source_world_rotation, dtype=float) @ FORWARD, turn=facing,
        facing_deg=facing_deg, arm_ratios=arms, aligned_rest=aligned_rest, keyed=tuple(sorted(keyed)),
    )  # fmt: skip


def _alignment(source: Skeleton, target: Skeleton, bone_map: dict[str, str], facing: np.ndarray
               ) -> dict[str, np.ndarray]:  # fmt: skip
    """Our bone -> the world rotation turning its target's rest segment onto ours turned by ``facing``
    (:data:`ALIGNED` bones only, the smallest such turn: the segment's twist is taken as the same); a segment
    without a mapped end takes its parent's turn. Legs, spine, pelvis and shoulder girdle are taken as standing
    alike (a stance is kept)."""
    turns: dict[str, np.ndarray] = {}
    for ours in source.names:  # parents first
        if ours not in ALIGNED or ours not in bone_map:
            continue
        end = next((e for e in ALIGNED[ours] if e in bone_map and e in source.names), None)
        if end is None:
            parent = source.names[source.parents[source.index(ours)]]
            turns[ours] = turns.get(parent, np.eye(3))
            continue
        mine = source.heads[source.index(end)] - source.heads[source.index(ours)]
        theirs = target.heads[target.index(bone_map[end])] - target.heads[target.index(bone_map[ours])]
        turns[ours] = rotation_between(theirs, facing @ mine)
    return turns


def forward_kinematics(
    target: Skeleton, rotations: dict[int, np.ndarray], hips: int, hips_at: np.ndarray
) -> np.ndarray:
    """(B, 4, 4) world poses: bones in ``rotations`` turned to those world rotations, ``hips`` moved to ``hips_at``,
    every other bone at rest relative to its parent."""
    poses = np.empty_like(target.rest)
    for b in range(len(target.names)):
        p = int(target.parents[b])
        chain = target.rest[b].copy() if p < 0 else poses[p] @ rigid_inverse(target.rest[p]) @ target.rest[b]
        if b in rotations:
            chain[:3, :3] = rotations[b]
        if b == hips:
            chain[:3, 3] = hips_at
        poses[b] = chain
    return poses


def pose_frame(plan: Plan, source_pose: np.ndarray, pinned: Iterable[str] = (), hand_goals: str = "body"
               ) -> tuple[np.ndarray, dict[str, float]]:  # fmt: skip
    """The target's world poses (B, 4, 4) for our world poses ``source_pose`` (S, 4, 4), and for each pinned limb
    (``foot_l``, ``hand_r``, ... of :data:`LIMBS`) how far (m) its end stays from its goal (0 when in reach).
    ``hand_goals``: ``body`` (our wrist scaled about the ankles) or ``arm`` (about the shoulder, by the arm ratio)."""
    src, tgt, face = plan.source, plan.target, plan.turn
    turn = face @ source_pose[:, :3, :3] @ np.swapaxes(src.rest[:, :3, :3], -1, -2) @ face.T  # world turns, theirs
    rotations = {t: turn[s] @ plan.aligned_rest[t] for t, s in plan.pairs.items()}
    ours, theirs = plan.hips
    pelvis_rest = plan.scaled(src.heads[ours])
    hips_at = plan.scaled(source_pose[ours, :3, 3]) + turn[ours] @ (tgt.heads[theirs] - pelvis_rest)
    poses = forward_kinematics(tgt, rotations, theirs, hips_at)
    misses: dict[str, float] = {}
    by_source = {s: t for t, s in plan.pairs.items()}
    for limb in pinned:
        upper, lower, end = (by_source[src.index(n)] for n in LIMBS[limb])
        s_upper, s_end = src.index(LIMBS[limb][0]), src.index(LIMBS[limb][2])
        goal = plan.scaled(source_pose[s_end, :3, 3])
        if limb.startswith("foot"):  # the target's own stance: its rest offset from our scaled ankle
            goal = goal + turn[s_end] @ (tgt.heads[end] - plan.scaled(src.heads[s_end]))
        elif hand_goals == "arm":  # our shoulder-to-wrist vector, scaled to the target's arm, from its shoulder
            reach = source_pose[s_end, :3, 3] - source_pose[s_upper, :3, 3]
            goal = poses[upper, :3, 3] + plan.arm_ratios[limb] * face @ reach
        pole = turn[ours] @ plan.forward * (1.0 if limb.startswith("foot") else -1.0)
        q1, q2, misses[limb] = two_bone_ik(poses[upper, :3, 3], poses[lower, :3, 3], poses[end, :3, 3], goal, pole)
        rotations[upper] = q1 @ rotations[upper]
        rotations[lower] = q2 @ q1 @ rotations[lower]
    if misses:
        poses = forward_kinematics(tgt, rotations, theirs, hips_at)
    return poses, misses


def solve_motion(plan: Plan, source_poses: np.ndarray, pinned: list[list[str]], hand_goals: str = "auto",
                 step: Callable[[int], None] | None = None
                 ) -> tuple[np.ndarray, list[dict[str, float]], str]:  # fmt: skip
    """Per frame of ``source_poses`` (F, S, 4, 4) with its pinned limbs: (the target's poses (F, B, 4, 4), the
    misses (m) per frame, the hand goals used). ``auto``: ``body`` goals unless a pinned hand misses one by more
    than :data:`REACH_M` at some frame, then ``arm`` goals for the whole motion (no jump between the two).
    ``step(frames done)`` after each frame (progress)."""
    if hand_goals not in HAND_GOALS:
        raise ModelError(f"hand goals: expected one of {', '.join(HAND_GOALS)}, got {hand_goals!r}")
    modes = ("body", "arm") if hand_goals == "auto" else (hand_goals,)
    for mode in modes:
        done = []
        for pose, limbs in zip(source_poses, pinned, strict=True):
            done.append(pose_frame(plan, pose, limbs, mode))
            if step is not None:
                step(len(done))
        hands = [m for _, misses in done for k, m in misses.items() if k.startswith("hand")]
        if mode == modes[-1] or max(hands, default=0.0) <= REACH_M:
            break
    return np.array([p for p, _ in done]), [m for _, m in done], mode


def miss_cause(plan: Plan, limb: str, hand_goals: str) -> str:
    """Why a pinned ``limb`` (``hand_l``, ``foot_r``, ...) misses its goal, in a phrase."""
    if limb.startswith("foot"):
        return "the character's hips sit farther from its feet than the manikin's, scaled"
    if hand_goals == "arm":
        return ("the character's upper arm and forearm are in other proportions than the manikin's, so its arm "
                "cannot fold or stretch as far")  # fmt: skip
    arm = plan.arm_ratios[limb]
    if arm < plan.ratio - 0.01:
        return (f"the character's arms are relatively shorter than the manikin's (arm ratio {arm:.3f}, leg ratio "
                f"{plan.ratio:.3f}): use arm-relative hand goals")  # fmt: skip
    return "the character's shoulders sit elsewhere relative to its hips than the manikin's, scaled"


def basis_matrices(target: Skeleton, poses: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """(B, 4, 4) local transforms (Blender's ``matrix_basis``) giving world poses ``poses``: pose = parent pose
    parent rest^-1 rest basis. ``scale``: the armature object's uniform scale (translations in its units)."""
    out = np.empty_like(poses)
    for b in range(len(target.names)):
        p = int(target.parents[b])
        parent = np.eye(4) if p < 0 else poses[p] @ rigid_inverse(target.rest[p])
        out[b] = rigid_inverse(parent @ target.rest[b]) @ poses[b]
    out[:, :3, 3] /= scale
    return out
