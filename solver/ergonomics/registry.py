"""Every ergonomic score the ``ergo`` report holds, by name: one module per score (a :class:`.base.Score`), one
``register`` line here.

The order of the lines is the order of the report's "sources"; in a report frame, in the CSV and in a study row
the frame scores come in this order, then the motion scores (:class:`.base.MotionScore`: their values wait for
the whole motion). A study records each score's :meth:`~.base.Score.study_columns` (a group of its
``record`` list under the score's name).
"""

from __future__ import annotations

from .base import MotionScore, Score
from .niosh import Niosh
from .owas import Owas
from .reba import Reba
from .rula import Rula
from .worksheet import Worksheet

# report frame keys that are not scores (a score of one of these names would overwrite them)
RESERVED = frozenset({"frame", "converged", "status", "posture", "joint_loads", "l4_l5", "strength", "shortfall"})
SCORES: dict[str, Score] = {}


def register(score: Score) -> Score:
    """Add ``score`` to the report (after the scores registered before it); a name taken is a ValueError."""
    if score.name in SCORES or score.name in RESERVED:
        raise ValueError(f"ergonomic score name {score.name!r} is taken")
    SCORES[score.name] = score
    return score


register(Rula())
register(Reba())
register(Owas())
register(Niosh())
register(Worksheet())

RANKING = "reba"  # the score whose worst frame a long motion's summary names (``highest_reba``)


def frame_scores() -> list[Score]:
    """The scores of one frame each, in registration order."""
    return [s for s in SCORES.values() if not isinstance(s, MotionScore)]


def motion_scores() -> list[MotionScore]:
    """The scores of the whole motion, in registration order."""
    return [s for s in SCORES.values() if isinstance(s, MotionScore)]


def in_frame_order() -> list[Score]:
    """Every score in the order of a report frame's entries: the frame scores, then the motion scores."""
    return [*frame_scores(), *motion_scores()]


def verdicts(frame: dict) -> list[dict]:
    """How every score rates one report frame, for the sidebar: each :meth:`~.base.Score.verdict` (text, level,
    severity) with the score's name and title, in report order (a score with nothing to say left out)."""
    out = []
    for score in in_frame_order():
        verdict = score.verdict(frame)
        if verdict is not None:
            out.append(verdict.as_dict() | dict(score=score.name, title=score.title))
    return out
