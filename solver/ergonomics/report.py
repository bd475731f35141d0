"""The evaluation of a whole result file and its outputs: per-frame JSON and a CSV with one row per frame."""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path

import numpy as np

from ..body.model import Model
from ..errors import UsageError
from ..io.files import open_output
from ..io.files import write_json as write_file
from ..io.result.frame import Frame
from . import postures
from .base import FrameInputs, MotionScore
from .loads import JointLoads, hand_load_kg, load_arrays
from .manikin import feet_frame, strengths, working_area
from .options import ErgoOptions
from .registry import RANKING, SCORES, frame_scores, in_frame_order, motion_scores

BASE_SOURCES = {  # the sources of what every report holds besides the scores
    "joint_loads": "Delfs 2012 eq. 3.11 (moments of gravity, contacts and loads over each joint's subtree)",
    "strength": "solver/body/humans/anthropometry.py: Anderson et al. 2007 (hip, knee, ankle); one trained subject "
    "(rbdl data) for shoulder, elbow, wrist, lumbar flexion/extension; other joints estimates",
    "l4_l5": "estimate: single equivalent muscle, 5 cm moment arm (Chaffin, Andersson & Martin, Occupational "
    "Biomechanics); limits 3400 / 6400 N (NIOSH 1981)",
}


def sources() -> dict[str, str]:
    """The report's "sources": the loads', then each registered score's (:meth:`.base.Score.sources`)."""
    out = dict(BASE_SOURCES)
    for score in SCORES.values():
        out |= score.sources()
    return out


SOURCES = sources()  # as the scores registered in .registry have them (the Blender layer's report imports it)


_PLAIN = (str, int, bool, type(None))  # JSON values clean keeps as they are
_KEPT = frozenset(_PLAIN)


def clean(value):
    """JSON-safe copy: numpy scalars to Python, non-finite floats to None."""
    kind = type(value)
    if kind is float:  # the common cases first, by exact type: a long motion cleans millions of values
        return value if math.isfinite(value) else None
    if kind is dict:  # a plain value or a float told here, without a call per value (x - x is 0.0 iff finite)
        return {k if type(k) is str else str(k): v if type(v) in _KEPT else (v if v - v == 0.0 else None)
                if type(v) is float else clean(v) for k, v in value.items()}  # fmt: skip
    if kind is list or kind is tuple:
        return [clean(v) for v in value]
    if kind in _PLAIN:
        return value
    if isinstance(value, dict):
        return {str(k): clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [clean(v) for v in value]
    if isinstance(value, (np.floating, float)):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.bool_):
        return bool(value)
    return value


def frame_report(
    f: Frame, options: ErgoOptions, model: Model | None, area, motion: dict[str, dict] | None
) -> tuple[dict, str]:
    """The ergonomics of one frame (JSON-safe) and where its joint strengths came from. ``area``: the working
    area of ``model`` (or None); ``motion``: the motion scores' values (:func:`motion_values`; the NIOSH lift,
    whose D and FM every frame's NIOSH values use), None: their per-frame entries are left out (a caller that
    evaluates each frame before the motion is known adds them later)."""
    report, loads, strength_note = frame_parts(f, options, model, area, motion)
    report["joint_loads"] = loads.as_dict()
    return report, strength_note


HEAD_KEYS = ("frame", "converged", "status")  # a report frame's first entries, and its CSV row's first cells


def frame_head(f: Frame) -> dict:
    """A report frame's :data:`HEAD_KEYS` entries (JSON-safe): its number and how its solve went."""
    return clean(dict(frame=f.number, converged=f.converged, status=f.status()))


def frame_parts(
    f: Frame, options: ErgoOptions, model: Model | None, area, motion: dict[str, dict] | None
) -> tuple[dict, JointLoads, str]:
    """:func:`frame_report` with its ``joint_loads`` (None in the report) as arrays, their ``l4_l5`` JSON-safe: the
    report, the loads, where the strengths came from. A long motion writes the loads as text from the arrays
    (:mod:`.report_text`) without building a dict per joint."""
    strength, strength_note = strengths(f, model)
    loads = load_arrays(f, strength)
    feet = feet_frame(f.tcp_position, f.tcp_rotation)  # once: the posture, the worksheet and NIOSH all use it
    posture = postures.measure(f, feet)
    load_kg = options.load_mass if options.load_mass is not None else hand_load_kg(f)
    inputs = FrameInputs(f, posture, load_kg, loads, area, options, motion or {}, feet)
    head = frame_head(f)
    evaluated = frame_scores() + (motion_scores() if motion is not None else [])
    scores = {score.name: score.evaluate(inputs) for score in evaluated}
    loads.l4_l5 = clean(loads.l4_l5)
    # joint_loads: JSON-safe already (JointLoads.as_dict), the bulk of a frame's values; the posture made JSON-safe
    # as it is rounded: clean walks only the scores' entries
    entry = clean(posture) if "reason" in posture else postures.rounded(posture, clean)
    return {**head, "posture": entry, "joint_loads": None, **clean(scores)}, loads, strength_note


def end_positions(score: MotionScore, numbers: Sequence[int | None], options: ErgoOptions) -> tuple[int, int]:
    """Where in a motion with these frame numbers the ``score``'s action starts and ends (indices; a number twice:
    its last frame). A number the options give that is no frame of the motion is one UsageError line."""
    if not numbers:
        raise UsageError("the result has no frames")
    (start_key, start), (end_key, end) = score.ends(options).items()
    return _position(start_key, start, numbers, 0), _position(end_key, end, numbers, len(numbers) - 1)


def _position(what: str, number: int | None, numbers: Sequence[int | None], default: int) -> int:
    if number is None:
        return default
    hits = [i for i, n in enumerate(numbers) if n == number]
    if not hits:
        shown = numbers if len(numbers) <= 6 else [numbers[0], numbers[1], "...", numbers[-1]]
        listed = ", ".join(map(str, shown))
        raise UsageError(f"{what} {number}: not a frame of the result (its frames: {listed})")
    return hits[-1]


def motion_values(frames: Sequence[Frame], options: ErgoOptions) -> dict[str, dict]:
    """Each motion score's value over ``frames`` (by name): the report's top-level entries."""
    numbers = [f.number for f in frames]
    out = {}
    for score in motion_scores():
        start, end = end_positions(score, numbers, options)
        out[score.name] = score.motion(frames[start], frames[end], options)
    return out


def report_head(
    options: ErgoOptions,
    model_note: str,
    strength_note: str,
    area,
    motion: dict[str, dict],
    result: str | None = None,
    scenario: str | None = None,
) -> dict:
    """The report's entries other than its frames (see :func:`evaluate_frames`), JSON-safe: ``motion`` (the motion
    scores' values) last."""
    return clean(
        dict(
            result=result,
            scenario=scenario,
            manikin=model_note,
            strength=strength_note,
            working_area=area.as_dict() if area is not None else None,
            options=asdict(options),
            sources=sources(),
            **motion,
        )
    )


def evaluate_frames(
    frames: Sequence[Frame],
    options: ErgoOptions,
    model: Model | None,
    model_note: str,
    result: str | None = None,
    scenario: str | None = None,
) -> dict:
    """Everything for every frame (see the README section of the ``ergo`` command). ``model`` supplies strengths
    the frames lack and the working area (``model_note`` says where it came from); ``result`` and ``scenario``
    name the files the report is about."""
    area = working_area(model) if model is not None else None
    motion = motion_values(frames, options)
    out, strength_note = [], ""
    for f in frames:
        report, strength_note = frame_report(f, options, model, area, motion)
        out.append(report)
    return report_head(options, model_note, strength_note, area, motion, result, scenario) | dict(
        frames=out,
        not_converged=[f.number for f in frames if f.converged is False],
        not_held=[f.number for f in frames if f.broken],
    )


def write_json(report: dict, path: Path) -> None:
    """The report as JSON (no NaN: :func:`clean` made them null)."""
    write_file(path, report, allow_nan=False)


def csv_header(first: dict, joints: list[str]) -> list[str]:
    """The CSV's columns: the frame's status, every score's columns (:func:`.registry.in_frame_order`; ``first``:
    the first frame's report) and the percent of strength of the ``joints`` shown."""
    header = list(HEAD_KEYS)
    for score in in_frame_order():
        header += score.columns(first)
    return header + [f"pct_{j}" for j in joints]


def csv_row(f: dict, joints: list[str]) -> list:
    """One frame's row (as :func:`csv_header`), from its report."""
    row = [f.get(key) for key in HEAD_KEYS]
    for score in in_frame_order():
        row += score.cells(f)
    return row + [f["joint_loads"][j]["percent_strength"] for j in joints]


def csv_cells(row: list) -> list:
    """A row as written: None empty, floats rounded to 4 decimals."""
    return ["" if v is None else round(v, 4) if isinstance(v, float) else v for v in row]


def csv_rows(report: dict) -> tuple[list[str], list[list]]:
    """Header and rows: one row per frame with its scores' columns (the worksheet's hold the body angles, L4/L5
    and the levels) and the percent of strength of every joint that has a strength."""
    frames = report["frames"]
    joints = [
        j for j in (frames[0]["joint_loads"] if frames else {})
        if j != "l4_l5" and any(f["joint_loads"][j]["percent_strength"] is not None for f in frames)
    ]  # fmt: skip
    return (csv_header(frames[0], joints) if frames else []), [csv_row(f, joints) for f in frames]


def plot_paths(stem: Path) -> list[Path]:
    """The PNG plots of a report: ``<stem>_loads.png``, ``<stem>_scores.png``, ``<stem>_back.png``."""
    return [stem.with_name(f"{stem.name}_{name}.png") for name in ("loads", "scores", "back")]


def output_files(output: str | Path, plots: bool = True) -> list[Path]:
    """What a report ``output`` (JSON) comes with: [the JSON, the CSV beside it (same stem), the plots if asked]."""
    output = Path(output)
    return [output, output.with_suffix(".csv")] + (plot_paths(output.with_suffix("")) if plots else [])


def write_csv(report: dict, path: Path) -> None:
    header, rows = csv_rows(report)
    with open_output(path) as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for row in rows:
            w.writerow(csv_cells(row))


def summary_lines(report: dict) -> list[str]:
    """What ``ergo`` prints: a line per frame (the first and last of a long motion) with each score's words, the
    frames that did not converge, the motion scores' lines (the NIOSH lift) and the files written. ``report``:
    what :func:`solver.ergonomics.run` returns (its ``frames`` are the ones shown; ``frame_count`` and
    ``highest_reba`` cover them all) or a whole report."""
    frames = report["frames"]
    count = report.get("frame_count", len(frames))
    shown = frames if len(frames) <= 10 else [frames[0], frames[-1]]
    lines = []
    for f in shown:
        words = [w for w in (score.brief(f) for score in in_frame_order()) if w is not None]
        flag = "" if f["converged"] is not False else f"  [NOT converged: {f['status']}]"
        lines.append(f"frame {f['frame']}: " + ", ".join(words) + flag)
    missed, held = report.get("not_converged", []), report.get("not_held", [])
    if count > len(shown):
        ranking = SCORES[RANKING]
        worst = report.get(f"highest_{RANKING}") or max(frames, key=lambda f: f[RANKING][ranking.value] or 0)
        of = " (of the converged frames)" if missed and len(missed) < count else ""
        lines.append(f"... {count} frames; highest {ranking.title} {worst[RANKING][ranking.value]} at frame "
                     f"{worst['frame']}{of}")  # fmt: skip
    if missed:
        lines.append(f"NOT converged: {len(missed)} of {count} frames {_frame_list(missed)}; their scores "
                     f"describe the solver's closest pose" + (f"; supports or balance NOT held in "
                     f"{_frame_list(held)}: loads there are not physical" if held else ""))  # fmt: skip
    for score in motion_scores():
        lines += score.motion_lines(report)
    lines.append("wrote " + ", ".join(report["written"]))
    return lines


def _frame_list(numbers: list[int], shown: int = 8) -> str:
    text = ", ".join(map(str, numbers[:shown]))
    return f"[{text}{', ...' if len(numbers) > shown else ''}]"
