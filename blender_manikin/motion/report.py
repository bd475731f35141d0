"""The report of a baked motion (plain Python, no bpy): per frame how the solve went and its ergonomics.

Each frame holds ``frame``, ``converged``, ``iterations``, ``time_s`` (solver), ``wall_s`` (with reading the
scene), ``unmet``, ``notes``, ``residuals`` (per constraint in its own units) and ``ergonomics`` (posture, joint
loads and every registered score's entry at that frame, as ``python -m solver ergo`` has them: RULA, REBA, OWAS,
the worksheet, then the motion scores' (NIOSH)). Top level: the source, the manikin, the range, the frames that
did not converge, timing, each motion score's value under its name (``niosh``: the NIOSH lift from the first to
the last frame), the sources and, for a bake stopped by Ctrl-C, ``interrupted``. Written frame by frame
(:class:`MotionReport`). The scores are those of :mod:`solver.ergonomics.registry`: none is named here.
"""

from __future__ import annotations

import json
import os
import tempfile
from dataclasses import asdict, fields
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ...solver.ergonomics import ErgoOptions, checked
from ...solver.ergonomics.held import HeldFrames
from ...solver.ergonomics.loads import JointLoads
from ...solver.ergonomics.manikin import working_area
from ...solver.ergonomics.registry import frame_scores, motion_scores
from ...solver.ergonomics.report import clean, sources
from ...solver.ergonomics.report_text import LoadsText, dumps_filled
from ...solver.ergonomics.stream import PlotSeries
from ...solver.errors import ManikinError
from ...solver.io.files import open_output
from ...solver.io.result.frame import Frame, ResultFrames
from ...solver.io.result.frame_text import SLOT
from .frame_store import FrameStore

if TYPE_CHECKING:
    from ...solver import Model, Result
    from ...solver.body.state import State
    from ...solver.ergonomics.base import Score
    from .bake import Baker, FrameRecord

PARTS = ("posture", "joint_loads")  # a frame's ergonomics before the scores' entries
HEAD = ("source", "manikin", "armature", "frame_start", "frame_end", "converged", "not_converged", "timing",
        "working_area", "ergonomics_options", "ergonomics_sources", "interrupted", "frames")  # fmt: skip


def valued() -> list[Score]:
    """The frame scores with one number per frame (RULA, REBA): what captions and summary lines show."""
    return [s for s in frame_scores() if s.value is not None]


def _shown(value: float | int) -> str:
    return str(value) if isinstance(value, int) else f"{round(value, 2):g}"


class MotionReport:
    """The report of a motion, built as it is baked (:meth:`add` per frame): each frame's record and ergonomics
    go to ``NAME.frames.tmp`` beside the report; :meth:`write` adds the motion scores' values (the NIOSH lift from
    the first to the last frame) and their entry in every frame and writes the report. Kept per frame only what
    the plots, captions and summary lines show and what each motion score keeps of a frame (the hands' point).

    ``body`` (the manikin's preset name or body file) only names it; the strengths are those of ``model``. The
    scores are those registered when the report is made. ``store``: keep each frame's sidebar entry too
    (:class:`.frame_store.FrameStore`, stored on the armature by the bake).
    """

    def __init__(self, model: Model, body: str, path: Path | None, plots: bool, store: bool = False) -> None:
        self.options = checked(ErgoOptions(manikin=body or None))
        self.model, self.body, self.area = model, body, working_area(model)
        self.valued, self.motions = valued(), motion_scores()
        self.parts = (*PARTS, *(s.name for s in frame_scores()))  # then the motion scores', known at the end
        taken = [s.name for s in self.motions if s.name in HEAD]
        if taken:
            raise ValueError(f"motion score name {taken[0]!r} is a key of the bake report")
        self.series = PlotSeries() if plots else None
        self.store = FrameStore(model) if store else None
        self.shown: list[tuple] = []  # per frame: the valued scores, trunk bend and L4/L5 compression (summary)
        self.kept: list[dict] = []  # per frame: what each motion score keeps of it (by name)
        self.ends: list[Frame] = []  # the first and the latest frame: where the motion scores' actions start, end
        self.path = None if path is None else Path(os.path.abspath(path))  # a device path stays itself
        # each frame's part, kept in a temporary file until the motion scores (and so their entries) are known
        self._frames = None if self.path is None else tempfile.TemporaryFile("w+", encoding="utf-8")
        self._loads, self._loads_text = LoadsText(), ""
        self._parts = HeldFrames(self.options, model, self.area, None)  # a held pose's ergonomics computed once
        self._fields: list[str] = []  # a frame record's fields, in order
        self._frame_of = ResultFrames()  # a held pose's frames share their arrays

    def add(self, record: FrameRecord, result: Result, state: State | None = None) -> None:
        """One baked frame (``state``: the result's, if the caller has it): its ergonomics, appended to the frames
        file."""
        f = self._frame_of(result, record.frame, state)
        ergo, loads, _ = self._parts(f)
        self.ends = [self.ends[0] if self.ends else f, f]
        self.kept.append({s.name: s.keep(f) for s in self.motions})
        if self.series is not None:
            self.series.add(ergo, loads)
        if self.store is not None:  # the scores' words read the L4/L5 compression
            self.store.add(record, result, ergo | {"joint_loads": {"l4_l5": loads.l4_l5}}, loads.percent)
        compression = loads.l4_l5.get("compression")
        trunk = ergo["posture"].get("trunk_flexion")
        values = tuple(ergo[s.name].get(s.value) for s in self.valued)
        self.shown.append((record.frame, record.converged, values, trunk, compression))
        if self._frames is not None:  # left open: the motion scores' entries come at the end
            try:
                self._frames.write(self._text(record, ergo, loads)[:-2] + "\n")
            except OSError as exc:  # the system's temporary folder is full: one line naming the report
                why = f"its frames' temporary file: {exc.strerror or exc}"
                raise ManikinError(f"{self.path}: cannot write ({why})") from None

    def _text(self, record: FrameRecord, ergo: dict, loads: JointLoads) -> str:
        """The frame's JSON: the record, then the ergonomics (the joint loads written from their arrays)."""
        self._fields = self._fields or [f.name for f in fields(record)]
        values = {name: getattr(record, name) for name in self._fields}  # asdict without its deep copy: clean copies
        frame = clean(values) | {"ergonomics": {k: ergo[k] for k in self.parts} | {"joint_loads": SLOT}}
        if not (self._parts.held and self._loads_text):  # a held pose's loads: the text written last
            self._loads_text = self._loads(loads)
        text = dumps_filled(frame, self._loads_text)
        if text is None:  # a note holding the slot's text: the dicts as they are
            frame["ergonomics"]["joint_loads"] = loads.as_dict()
            text = json.dumps(frame, allow_nan=False)
        return text

    def motion(self) -> dict[str, dict]:
        """Each motion score's value (by name) for the action from the first to the last frame added."""
        return {s.name: s.motion(self.ends[0], self.ends[-1], self.options) for s in self.motions}

    def summary(self) -> dict:
        """What :func:`captions` and :func:`summary_lines` read: per frame the valued scores, trunk bend and L4/L5
        compression, and the motion scores' values."""
        frames = [
            dict(frame=frame, converged=converged, ergonomics=dict(
                {s.name: {s.value: v} for s, v in zip(self.valued, values, strict=True)},
                posture={"trunk_flexion": trunk}, joint_loads={"l4_l5": {"compression": compression}}))
            for frame, converged, values, trunk, compression in self.shown
        ]  # fmt: skip
        return dict(frames=frames, **self.motion())

    def write(self, baker: Baker, source: dict, interrupted: dict | None = None) -> Path:
        """Write the report of the frames added (``interrupted``: where the bake stopped); its path."""
        motion, records = self.motion(), baker.records
        wall = np.array([r.wall_s for r in records])
        failed = [r.frame for r in records if not r.converged]
        timing = dict(
            solve_s=sum(r.time_s for r in records),
            wall_s=float(wall.sum()),
            median_frame_ms=1e3 * float(np.median(wall)),
            p95_frame_ms=1e3 * float(np.percentile(wall, 95)),
        )
        head = clean(dict(
            source=source, manikin=self.body, armature=baker.arm.name, frame_start=baker.frames[0],
            frame_end=baker.frames[-1], converged=not failed, not_converged=failed, timing=timing,
        ) | motion | dict(
            working_area=self.area.as_dict() if self.area is not None else None,
            ergonomics_options=asdict(self.options), ergonomics_sources=sources(),
        ) | ({} if interrupted is None else {"interrupted": interrupted}))  # fmt: skip
        frames = self._frames
        frames.seek(0)
        with frames, open_output(self.path) as out:
            out.write(json.dumps(head, allow_nan=False)[:-1] + ', "frames": [')
            for i, (line, kept) in enumerate(zip(frames, self.kept, strict=True)):
                entries = "".join(f", {json.dumps(s.name)}: " + json.dumps(
                    clean(s.at_frame(kept[s.name], motion[s.name], self.options)), allow_nan=False)
                    for s in self.motions)  # fmt: skip
                out.write(("\n" if i == 0 else ",\n") + line.rstrip("\n") + entries + "}}")
            out.write("\n]}\n")
        return self.path

    def plots(self, prefix: Path) -> list[Path]:
        """The ergonomics plots of ``python -m solver ergo`` (``PREFIX_loads.png``, ...)."""
        from ...solver.ergonomics.plots import write_plots

        return write_plots(self.series.report(), prefix)

    def discard(self) -> None:
        """Drop the frames kept so far (a run that ends without a report)."""
        if self._frames is not None:
            self._frames.close()


def _worst(report: dict, *keys: str) -> tuple[float | None, int | None]:
    best, at = None, None
    for f in report["frames"]:
        value = f["ergonomics"]
        for k in keys:
            value = value.get(k) if isinstance(value, dict) else None
        if isinstance(value, (int, float)) and (best is None or value > best):
            best, at = value, f["frame"]
    return best, at


def summary_lines(report: dict) -> list[str]:
    """A few lines for the terminal: the worst of each valued score and of the L4/L5 compression over the motion,
    then the motion scores' lines (the NIOSH lift)."""
    lines = []
    worst = [(s.title, *_worst(report, s.name, s.value)) for s in valued()]
    highest = [f"highest {title} {_shown(value)} (frame {at})" for title, value, at in worst if value is not None]
    if highest:
        lines.append(", ".join(highest))
    compression, at = _worst(report, "joint_loads", "l4_l5", "compression")
    if compression is not None:
        lines.append(f"L4/L5 compression up to {compression / 1e3:.2f} kN (frame {at}; NIOSH action limit 3.4 kN)")
    for score in motion_scores():
        if report.get(score.name) is not None:
            lines += score.motion_lines(report)
    return lines


def captions(report: dict | None) -> dict[int, str]:
    """A short caption per frame for the key-pose picture: the valued scores, trunk bend, L4/L5 compression."""
    out: dict[int, str] = {}
    scores = valued()
    for f in (report or {}).get("frames", []):
        e = f["ergonomics"]
        values = [(s.title, e.get(s.name, {}).get(s.value)) for s in scores]
        shown = [f"{title} {_shown(v)}" for title, v in values if isinstance(v, (int, float))]
        lines = [" · ".join(shown)] if shown else []
        trunk = e["posture"].get("trunk_flexion")
        if isinstance(trunk, (int, float)):
            lines.append(f"trunk bent {trunk:.0f}°")
        compression = e["joint_loads"].get("l4_l5", {}).get("compression")
        if isinstance(compression, (int, float)):
            lines.append(f"L4/L5 {compression / 1e3:.1f} kN")
        if not f["converged"]:
            lines.append("NOT converged")
        out[f["frame"]] = "\n".join(lines)
    return out


def choose_frames(frames: list[int], thetas: np.ndarray, keys: list[int], count: int = 4) -> list[int]:
    """``count`` frames worth showing: the ends and the targets' key frames, then the middle of whichever stretch
    changes the pose most, until there are ``count`` (evenly spaced frames when there are too many keys)."""
    first, last = frames[0], frames[-1]
    chosen = sorted({first, last} | {k for k in keys if first < k < last})
    if len(chosen) > count:
        return sorted({frames[round(i)] for i in np.linspace(0, len(frames) - 1, count)})
    while len(chosen) < count:
        gaps = [(a, b) for a, b in zip(chosen, chosen[1:], strict=False) if b - a > 1]
        if not gaps:
            break
        a, b = max(gaps, key=lambda g: float(np.linalg.norm(thetas[g[1] - first] - thetas[g[0] - first])))
        chosen = sorted({*chosen, (a + b) // 2})
    return chosen
