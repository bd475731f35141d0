"""The one interface every ergonomic score implements; :mod:`.registry` lists them, and the report, the CSV, the
plots, the ``ergo`` summary and the study take every score from there.

A :class:`Score` turns one frame's measurements (:class:`FrameInputs`) into a JSON-able entry of the report's frame
under its ``name``, then says how that entry is shown: its CSV columns, its words in the summary line, its panel in
the scores plot and what a study records of it over a motion. A :class:`MotionScore` is computed once for the
whole motion from the frames where an action starts and ends (the NIOSH lift) and then gives every frame a value.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ..io.result.frame import Frame
from .loads import JointLoads
from .manikin import WorkingArea
from .options import ErgoOptions


@dataclass(frozen=True)
class FrameInputs:
    """What every score of one frame is computed from.

    ``posture``: :func:`.postures.measure` of the frame (deg; ``{"reason": ...}`` for a body that is not human);
    ``load_kg``: kg in the hands (the options' load mass, else the result's loads on the hand TCPs); ``loads``: joint
    moments (N*m), percent of strength and L4/L5 (:class:`.loads.JointLoads`, ``l4_l5`` not yet JSON-cleaned);
    ``area``: the manikin's standard working area (None without one); ``motion``: the motion scores' values by name
    (the report's top-level entries; empty where the frame is evaluated before the motion is known); ``feet``: the
    frame's :func:`.manikin.feet_frame` when the caller has it (None: each score computes it, as for a body without
    feet).
    """

    frame: Frame
    posture: dict
    load_kg: float
    loads: JointLoads
    area: WorkingArea | None
    options: ErgoOptions
    motion: Mapping[str, dict] = field(default_factory=dict)
    feet: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None


@dataclass(frozen=True)
class Bands:
    """A score's panel in the scores plot: its title, the edges of the green / yellow / red bands on the value
    axis (4 numbers, in the score's units) and a legend saying what the bands mean."""

    title: str
    edges: tuple[float, float, float, float]  # the value axis spans the first to the last
    legend: str


SEVERITY = {"green": 0, "yellow": 1, "red": 2}  # a level's severity: 0 fine, 1 look into it, 2 act


@dataclass(frozen=True)
class Verdict:
    """How a score rates one frame, for the sidebar: ``text`` its words (:meth:`Score.brief`, "OWAS 2141"),
    ``level`` what that means in the method's own terms ("action category 2: slightly harmful, ...") and
    ``severity`` 0 (green: acceptable), 1 (yellow: investigate) or 2 (red: change it); None: not rated."""

    text: str
    level: str | None = None
    severity: int | None = None

    def as_dict(self) -> dict:
        return dict(text=self.text, level=self.level, severity=self.severity)


def peak(values: list) -> float | int | None:
    """The largest finite value (None and NaN left out); None if there is none."""
    finite = [v for v in values if v is not None and math.isfinite(v)]
    return max(finite) if finite else None


class Score(ABC):
    """A score of one frame. Subclasses set the class attributes and :meth:`evaluate`; the other methods have
    defaults for a score with one number per frame (``value``), shown as a column named after the score."""

    name: ClassVar[str]  # the key of its entry in a report frame, its study group, the start of its CSV columns
    title: ClassVar[str]  # how people write it: the summary line, plot labels ("RULA")
    source: ClassVar[str]  # the publication it follows (the report's "sources")
    value: ClassVar[str | None] = "score"  # the entry's key of its one number per frame (None: it has none)
    bands: ClassVar[Bands | None] = None  # its panel in the scores plot (None: not drawn there)
    # its entry reads only the frame's pose, contacts and loads, not its number or how its solve went: a held pose's
    # entry is computed once (.held.HeldFrames; a score that reads the number must leave it False)
    pose_only: ClassVar[bool] = False

    @abstractmethod
    def evaluate(self, inputs: FrameInputs) -> dict:
        """The frame's entry (JSON-able once :func:`.report.clean` has run; a body it cannot score gets an entry
        with ``reason`` and its value None)."""

    def sources(self) -> dict[str, str]:
        """The report's "sources" entries this score adds (name: publication)."""
        return {self.name: self.source}

    def columns(self, first: dict) -> list[str]:
        """Its CSV columns, given the report of the first frame (``first``)."""
        return [self.name]

    def cells(self, frame: dict) -> list:
        """Its CSV values of one frame's report, in the order of :meth:`columns` (None: an empty cell)."""
        return [frame[self.name].get(self.value)]

    def brief(self, frame: dict) -> str | None:
        """Its words in the ``ergo`` summary line of one frame's report (None: it says nothing there)."""
        return f"{self.title} {frame[self.name].get(self.value)}"

    def verdict(self, frame: dict) -> Verdict | None:
        """Its words in one frame's report with the level they stand for and its severity (the sidebar's lines;
        None: it says nothing of a frame). The default: :meth:`brief`'s words, not rated."""
        words = self.brief(frame)
        return None if words is None else Verdict(words)

    def graph(self, frame: dict) -> float | None:
        """The one number per frame a motion's graph shows of it (its ``value``; a rated score without one may give
        its level's number), None where it has none."""
        v = frame[self.name].get(self.value) if self.value is not None else None
        return float(v) if isinstance(v, (int, float)) else None

    def details(self, frame: dict) -> list[tuple[str, int | None]]:
        """Lines a frame's panel lists under the score (a worksheet's items), each with its severity."""
        return []

    def study_columns(self) -> list[str]:
        """The columns a study row records of it (the peak of its value over the motion's frames)."""
        return [f"{self.name}_peak"] if self.value is not None else []

    def summarise(self, report: dict) -> dict:
        """A study row's values of :meth:`study_columns` from a whole ergonomics report."""
        if self.value is None:
            return {}
        return {f"{self.name}_peak": peak([f[self.name].get(self.value) for f in report["frames"]])}

    def motion_lines(self, report: dict) -> list[str]:
        """Lines the ``ergo`` summary prints about the whole motion (after the frames' lines)."""
        return []


class MotionScore(Score):
    """A score of an action between two frames of the motion (the NIOSH lift), computed once (:meth:`motion`, the
    report's top-level entry under ``name``) and then given at every frame (:meth:`at_frame`, from what
    :meth:`keep` took of the frame, so a caller that sees each frame before the motion is known keeps only that).
    Its per-frame entries come after every frame score's (they wait for the motion)."""

    value = None

    @abstractmethod
    def ends(self, options: ErgoOptions) -> dict[str, int | None]:
        """The frame numbers where the action starts and ends, by the option that names each (two entries, the
        start first); None: the motion's first (start) or last (end) frame."""

    @abstractmethod
    def motion(self, start: Frame, end: Frame, options: ErgoOptions) -> dict:
        """The motion's value from its start and end frames (the same object when they are one frame)."""

    @abstractmethod
    def keep(self, frame: Frame) -> object:
        """What :meth:`at_frame` needs of a frame (small: it is kept for every frame of a motion)."""

    @abstractmethod
    def at_frame(self, kept: object, motion: dict, options: ErgoOptions) -> dict | None:
        """A frame's entry from what :meth:`keep` took of it and the motion's value."""

    def evaluate(self, inputs: FrameInputs) -> dict | None:
        return self.at_frame(self.keep(inputs.frame), inputs.motion[self.name], inputs.options)

    def brief(self, frame: dict) -> str | None:
        return None

    def verdict(self, frame: dict) -> Verdict | None:
        return None

    def graph(self, frame: dict) -> float | None:
        return None
