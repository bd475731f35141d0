"""Which of the body's capsules are kept apart from each other (self-collision), and how far apart at least.

The pairs (checked by name, so every human preset and body file has them and the snake has none):

- each hand and forearm against the trunk (pelvis, every vertebra with mass up to the neck), the head and both
  thighs — the parts a reach, a carry or an overhead task can drive an arm through;
- the two shanks against each other (knees and shins of a squat or a turn).

Neighbours and near neighbours never pair (a hand and its own forearm, the thigh and the pelvis it hangs from):
their capsules meet at the shared joint by construction. The upper arms are not paired with the trunk: they hang
against it in every standing pose and the shoulder's own range keeps them out.

The capsules are rough (a round trunk; see :mod:`.body`), so some pairs overlap in the zero pose (an arm hanging
beside the pelvis, a hand against the thigh). Such a pair may overlap as much as it does in the zero pose and no
more: its least distance is min(0, zero-pose distance) (m); every other pair keeps 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..body.model import Model
from .body import BodyCapsules
from .distance import capsule_pairs

REACHING = ("hand_r", "forearm_r", "hand_l", "forearm_l")  # what a task drives through the body
THIGHS = ("thigh_r", "thigh_l")
SHANKS = ("shank_r", "shank_l")
TRUNK_ENDS = ("pelvis", "head")  # the trunk: every capsule on the chain from the pelvis to the head


@dataclass(frozen=True)
class SelfPairs:
    """Capsule ``first[m]`` vs capsule ``second[m]`` (indices into the body's capsules) keep at least
    ``least[m]`` (m) between their surfaces."""

    first: np.ndarray  # (pairs,) int
    second: np.ndarray  # (pairs,) int
    least: np.ndarray  # (pairs,) m

    def __len__(self) -> int:
        return len(self.first)


def self_pairs(model: Model, capsules: BodyCapsules) -> SelfPairs:
    """The pairs of the module docstring that ``model``'s capsules have, with their least distances."""
    index = {name: k for k, name in enumerate(capsules.names)}
    trunk = [index[model.link_names[link]] for link in _trunk_links(model, capsules)]
    blocking = trunk + [index[name] for name in THIGHS if name in index]
    first, second = [], []
    for name in REACHING:
        if name in index:
            first += [index[name]] * len(blocking)
            second += blocking
    if all(name in index for name in SHANKS):
        first.append(index[SHANKS[0]])
        second.append(index[SHANKS[1]])
    first_a, second_a = np.array(first, dtype=int), np.array(second, dtype=int)
    zero = model.forward(model.zero_pose())
    p0, p1 = capsules.world(zero)
    at_rest = capsule_pairs(p0, p1, capsules.radius, first_a, second_a).distance if first else np.zeros(0)
    return SelfPairs(first_a, second_a, np.minimum(at_rest, 0.0))


def _trunk_links(model: Model, capsules: BodyCapsules) -> list[int]:
    """The links with a capsule from the pelvis to the head, both included; none when the body lacks either."""
    names = list(model.link_names)
    if not all(end in names for end in TRUNK_ENDS):
        return []
    pelvis, head = (names.index(end) for end in TRUNK_ENDS)
    return [int(k) for k in capsules.link if model.descendant[pelvis, k] and model.descendant[k, head]]
