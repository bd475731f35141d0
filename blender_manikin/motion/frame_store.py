"""What a bake keeps of each frame for the sidebar (plain Python, no bpy): the Result panel's summary of the frame
(converged, residuals, comfort, most loaded joints, contacts, the scores' words) and its ergonomics (each
registered score's verdict, graph number and detail lines), plus the motion's head: the motion scores' lines (the
NIOSH lift), the worst frames and, per rated score, where it is worst and why.

:class:`FrameStore` is filled frame by frame (:meth:`FrameStore.add`, from the ergonomics the bake's
:class:`.report.MotionReport` computes anyway) and gives JSON texts: one per frame and the head, which
:func:`..motion.bake.Baker.write` puts on the armature (``scene.schema.FRAMES_KEY``). The scores are those of
:mod:`solver.ergonomics.registry`: none is named here.
"""

from __future__ import annotations

import json
import math
from typing import TYPE_CHECKING

import numpy as np

from ...solver.ergonomics.registry import RANKING, SCORES, frame_scores, motion_scores, verdicts
from ...solver.iteration.result import shortfall_text
from .job_assess import POSE_KEY, pose_part

if TYPE_CHECKING:
    from ...solver import Model, Result
    from .bake import FrameRecord

TOP_LOADS = 3  # most loaded joints kept per frame (the Result panel's list)
WORST_SHOWN = 5  # worst frames listed in the panel
STORE_MAX = 5000  # frames whose entries a bake stores on the armature (about 3 kB each); a longer bake stores none
GRAPH_PREFIX = "manikin_"  # a score's graph: the custom property "manikin_<score name>" on the armature's data


def _short(value: float) -> float | None:
    """Four significant digits (the panel shows fewer): a compact JSON number; None where not finite."""
    return float(f"{value:.4g}") if math.isfinite(value) else None


def result_part(record: FrameRecord, result: Result, model: Model, percent: np.ndarray) -> dict:
    """The Result panel's summary of one baked frame (the keys ``scene.problem_io.summarize`` gives it)."""
    rank = np.where(np.isfinite(percent) & ~model.prismatic, percent, -1.0)
    top = [int(j) for j in np.argsort(-rank, kind="stable")[:TOP_LOADS] if rank[j] >= 0]
    tau = result.state.statics.axis_loads()
    return dict(
        converged=record.converged, iterations=record.iterations, time_ms=_short(1e3 * record.time_s),
        unmet=list(record.unmet), broken=list(result.broken), notes=list(record.notes),
        shortfall={name: shortfall_text(parts) for name, parts in result.shortfall.items()},
        residuals={k: _short(v) for k, v in record.residuals.items()},
        comfort=_short(float(result.comfort)),
        comfort_parts={k: _short(float(v)) for k, v in result.comfort_parts.items()},
        joint_loads=[(model.joint_names[j], _short(float(tau[j])), _short(float(percent[j]))) for j in top],
        contacts=[dict(tcp=c["tcp"], force=[_short(float(v)) for v in c["force"]]) for c in result.contacts],
    )  # fmt: skip


def ergonomics_part(ergo: dict) -> dict:
    """A frame's scores from its report frame (``ergo``: posture, joint loads' L4/L5, each frame score's entry):
    the words (``scores``), the verdicts, the graph numbers by score name and each score's detail lines."""
    rated = verdicts(ergo)  # a motion score's entry is not in ``ergo`` yet: it says nothing of a frame anyway
    return dict(
        scores=[v["text"] for v in rated],
        verdicts=rated,
        graph={s.name: g for s in frame_scores() if (g := s.graph(ergo)) is not None},
        details={s.name: d for s in frame_scores() if (d := s.details(ergo))},
    )


def severity(entry: dict) -> int:
    """A frame's worst severity over its verdicts (-1: none rated)."""
    return max((v["severity"] for v in entry["verdicts"] if v["severity"] is not None), default=-1)


def worst_frames(entries: list[dict], count: int = WORST_SHOWN) -> list[int]:
    """The ``count`` frames to look at first: the highest severity, then the most scores at it, then the ranking
    score's (REBA's) value; earlier frames first among equals."""

    def key(e: dict) -> tuple:
        top = severity(e)
        at_top = sum(v["severity"] == top for v in e["verdicts"])
        return (-top, -at_top, -(e["graph"].get(RANKING) or 0.0), e["frame"])

    return [e["frame"] for e in sorted(entries, key=key)[:count]]


def worst_of_each(entries: list[dict]) -> list[tuple[str, int, int]]:
    """Per rated score, where it is worst: (its words and level at that frame, the frame, the severity); the
    first frame among equals ("worksheet red at frame 23: worst level red: back bend 65 deg")."""
    out = []
    for score in frame_scores():
        best = None
        for e in entries:
            v = next((v for v in e["verdicts"] if v["score"] == score.name), None)
            if v is not None and v["severity"] is not None and (best is None or v["severity"] > best[1]["severity"]):
                best = (e["frame"], v)
        if best is not None:
            frame, v = best
            level = f" ({v['level']})" if v["level"] else ""
            out.append((f"{v['text']} at frame {frame}{level}", frame, v["severity"]))
    return out


class FrameStore:
    """The baked frames' sidebar entries, in order; :meth:`head` once the motion scores are known."""

    def __init__(self, model: Model) -> None:
        self.model = model
        self.entries: list[dict] = []

    def add(self, record: FrameRecord, result: Result, ergo: dict, percent: np.ndarray) -> None:
        """One baked frame: ``ergo`` its report frame (the scores' entries), ``percent`` its joints' percent of
        strength. The frame's pose goes in too: the Job panel rates the motion from it (:mod:`.job_assess`)."""
        entry = dict(frame=record.frame) | result_part(record, result, self.model, percent) | ergonomics_part(ergo)
        entry[POSE_KEY] = pose_part(result)
        self.entries.append(entry)

    def texts(self) -> dict[str, str]:
        """Each frame's entry as JSON, by frame number (a string: an ID property group's key)."""
        return {str(e["frame"]): json.dumps(e, allow_nan=False) for e in self.entries}

    def head(self, motion: dict[str, dict], result_crc: int) -> dict:
        """The motion's part: range, graph series (score name, title, custom property), the motion scores' lines
        and levels, the worst frames and each score's worst. ``motion``: the motion scores' values by name;
        ``result_crc``: the checksum of the Result panel's last solve when the bake ended (a later solve wins)."""
        graphs = sorted({name for e in self.entries for name in e["graph"]}, key=list(SCORES).index)
        lines = [line for s in motion_scores() if motion.get(s.name) is not None for line in s.motion_lines(motion)]
        levels = [(s.title, m.get("level")) for s in motion_scores() if isinstance(m := motion.get(s.name), dict)]
        return dict(
            frame_start=self.entries[0]["frame"], frame_end=self.entries[-1]["frame"], result_crc=result_crc,
            graphs=[(name, SCORES[name].title, GRAPH_PREFIX + name) for name in graphs],
            motion_lines=lines, motion_levels=[(t, lv) for t, lv in levels if lv is not None],
            worst=worst_frames(self.entries), worst_of_each=worst_of_each(self.entries),
        )  # fmt: skip

    def series(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Per graphed score, by its custom property's name, its frames and values (frames without a value left
        out), for the F-curves."""
        out: dict[str, tuple[list, list]] = {}
        for e in self.entries:
            for name, value in e["graph"].items():
                frames, values = out.setdefault(name, ([], []))
                frames.append(e["frame"])
                values.append(value)
        return {
            GRAPH_PREFIX + name: (np.array(f, dtype=float), np.array(v, dtype=float)) for name, (f, v) in out.items()
        }
