"""The ergonomics of a motion's frames one after another, a held pose's computed once: a frame whose every field
but the solve's status is the frame before's, bit for bit (:meth:`~solver.io.result.frame.Frame.same_pose`), gets
that frame's report again under its own head (number, converged, status) and the same joint loads object, when
every score evaluated reads only the pose (:attr:`.base.Score.pose_only`). A slow motion holds most of its frames
(the targets move less than their tolerance: the solver keeps the pose)."""

from __future__ import annotations

from ..body.model import Model
from ..io.result.frame import Frame
from .loads import JointLoads
from .options import ErgoOptions
from .registry import frame_scores, motion_scores
from .report import frame_head, frame_parts


class HeldFrames:
    """:func:`.report.frame_parts` of frame after frame with the same options, model, working area and motion
    values; ``held``: the last frame was the one before's pose (its parts given again)."""

    def __init__(self, options: ErgoOptions, model: Model | None, area, motion: dict[str, dict] | None) -> None:
        self.options, self.model, self.area, self.motion = options, model, area, motion
        self.held = False
        evaluated = frame_scores() + (motion_scores() if motion is not None else [])
        self._reuse = all(score.pose_only for score in evaluated)  # else every frame is computed
        self._frame: Frame | None = None  # the last frame whose parts were computed
        self._report: dict = {}
        self._loads: JointLoads | None = None
        self._note = ""

    def __call__(self, f: Frame) -> tuple[dict, JointLoads, str]:
        """(report, loads, where the strengths came from), as :func:`.report.frame_parts` gives them; a held pose's
        report is a new dict (its entries shared with the frame before's: read them, do not change them)."""
        self.held = self._reuse and f.same_pose(self._frame)
        if self.held:
            return self._report | frame_head(f), self._loads, self._note
        report, loads, note = frame_parts(f, self.options, self.model, self.area, self.motion)
        self._frame, self._report, self._loads, self._note = f, dict(report), loads, note
        return report, loads, note
