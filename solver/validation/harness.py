"""The validation run: read the manifest of key frames, make each a problem, solve it and measure both skeletons;
the per-key-frame rows and their summary (per split, per task kind, in total: mean, median and worst absolute
error per measure)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import ScenarioError
from ..io.files import read_toml
from ..presets import PRESETS_DIR
from .bvh import Bvh, read_bvh
from .keyframe import Subject, solve_key_frame, subject_body
from .measures import MEASURES, calibrated, measure
from .skeleton import cmu_points, model_skeleton, stature_and_floor, to_our_frame

MANIFEST = PRESETS_DIR / "validation" / "manifest.toml"
SPLITS = ("train", "held-out")
# CMU's capture floor is y = 0 (its standing frames' toe joints sit 4-7 cm above it). The reference frame's floor
# (:func:`stature_and_floor`) serves only that frame: its root height is copied from a frame whose legs may be bent.
CMU_FLOOR = 0.0


@dataclass
class KeyFrame:
    """One manifest entry: the excerpt frame of a subject, what the person does, which wrists hold targets."""

    name: str
    subject: str
    frame: int
    task: str
    style: str
    hands: tuple[str, ...]
    trial: str
    source_frame: int
    description: str
    source_exact: bool = False  # source_frame counted from a file end (True) or estimated from a page offset
    around: tuple[int, ...] = ()  # excerpt frames a few frames before and after, for a reader to check the key frame
    heel_raised: tuple[str, ...] = ()  # sides ("r", "l") whose heel is off the floor (the foot is planted flat)


def read_manifest(path: str | Path = MANIFEST) -> tuple[dict, dict[str, dict], list[KeyFrame]]:
    """The manifest's top table, its subjects by id and its key frames; a ScenarioError names a missing key."""
    path = Path(path)
    try:
        data = read_toml(path, ScenarioError)  # a folder, non-UTF-8, 5000 digits, deep nesting: one line
        subjects = {str(s["id"]): dict(s) for s in data["subjects"]}
        frames = [
            KeyFrame(k["name"], str(k["subject"]), int(k["frame"]), k["task"], k.get("style", ""),
                     tuple(k["hands"]), k["trial"], int(k["source_frame"]), k.get("description", ""),
                     bool(k.get("source_exact", False)), tuple(int(f) for f in k.get("around", ())),
                     tuple(k.get("heel_raised", ())))
            for k in data["keyframes"]
        ]  # fmt: skip
    except (OSError, KeyError, TypeError, ValueError, OverflowError) as exc:  # OverflowError: int(inf)
        raise ScenarioError(f"{path}: not a readable validation manifest ({type(exc).__name__}: {exc})") from None
    for k in frames:
        if k.subject not in subjects:
            raise ScenarioError(f"{path}: key frame {k.name!r} names unknown subject {k.subject!r}")
    return data, subjects, frames


class _SubjectData:
    """A subject's excerpt, stature, floor, body and upright measures (made once per run)."""

    def __init__(self, entry: dict, folder: Path) -> None:
        self.entry = entry
        self.bvh: Bvh = read_bvh(folder / entry["file"])
        reference = cmu_points(self.bvh, int(entry.get("reference", 0)))
        self.stature, self.floor = stature_and_floor(reference)
        self.subject = Subject(
            str(entry["id"]), entry.get("sex", "male"), self.stature, entry.get("mass"),
            float(np.linalg.norm(reference["elbow_r"] - reference["shoulder_r"])),
            float(np.linalg.norm(reference["wrist_r"] - reference["elbow_r"])),
        )  # fmt: skip
        self.model = subject_body(self.subject)
        self.upright = measure(to_our_frame(reference, self.floor), self.stature)
        self.ours_upright = measure(model_skeleton(self.model, self.model.zero_pose(), self.stature), self.stature)


def run_validation(path: str | Path = MANIFEST, split: str = "all", only: tuple[str, ...] = ()) -> dict:
    """Solve and measure every key frame of ``split`` ("train", "held-out" or "all"; ``only``: these names);
    ``{"rows": [...], "summary": {...}, "citation": ...}``."""
    path = Path(path)
    top, subjects, frames = read_manifest(path)
    chosen = [k for k in frames if split in ("all", subjects[k.subject]["split"]) and (not only or k.name in only)]
    if not chosen:
        raise ScenarioError(f"{path}: no key frame in split {split!r}" + (f" named {', '.join(only)}" if only else ""))
    loaded: dict[str, _SubjectData] = {}
    rows = []
    for k in chosen:
        if k.subject not in loaded:
            loaded[k.subject] = _SubjectData(subjects[k.subject], path.parent)
        rows.append(_row(k, loaded[k.subject]))
    return {"citation": top.get("citation", ""), "split": split, "rows": rows, "summary": summarize(rows)}


def _row(k: KeyFrame, s: _SubjectData) -> dict:
    """One key frame solved and measured."""
    measured = to_our_frame(cmu_points(s.bvh, k.frame), CMU_FLOOR)
    result = solve_key_frame(s.model, measured, k.hands)
    predicted = model_skeleton(s.model, result.theta, s.stature)
    m = calibrated(measure(measured, s.stature), s.upright, s.ours_upright)
    p = measure(predicted, s.stature)
    return {
        "name": k.name, "subject": k.subject, "split": s.entry["split"], "task": k.task, "style": k.style,
        "trial": k.trial, "source_frame": k.source_frame, "source_exact": k.source_exact, "around": list(k.around),
        "heel_raised": list(k.heel_raised), "hands": list(k.hands), "stature": s.stature,
        "converged": bool(result.converged), "unmet": list(result.unmet),
        "measured": m, "predicted": p, "error": {name: p[name] - m[name] for name in MEASURES},
        "skeletons": {
            "measured": {n: v.tolist() for n, v in measured.points.items()},
            "predicted": {n: v.tolist() for n, v in predicted.points.items()},
        },
    }  # fmt: skip


def _stats(rows: list[dict]) -> dict:
    """Per measure: mean and median absolute error and the worst key frame."""
    out = {}
    for name in MEASURES:
        errors = np.array([abs(r["error"][name]) for r in rows])
        worst = int(np.argmax(errors))
        out[name] = {
            "mean_abs": float(errors.mean()), "median_abs": float(np.median(errors)),
            "worst_abs": float(errors[worst]), "worst": rows[worst]["name"],
        }  # fmt: skip
    return out


def summarize(rows: list[dict]) -> dict:
    """``{"total": stats, "split": {name: stats}, "task": {kind: stats}, "converged": n, "count": n}``."""
    groups = {"split": {}, "task": {}}
    for key in groups:
        for value in dict.fromkeys(r[key] for r in rows):
            groups[key][value] = _stats([r for r in rows if r[key] == value])
    return {
        "count": len(rows), "converged": sum(r["converged"] for r in rows), "total": _stats(rows),
        "split": groups["split"], "task": groups["task"],
    }  # fmt: skip
