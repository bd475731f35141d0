"""The evaluation of a whole result file and its outputs: per-frame JSON and a CSV with one row per frame."""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path

import numpy as np

from ..body.model import Model
from ..io.files import open_output
from ..io.files import write_json as write_file
from ..io.result.frame import Frame
from . import niosh, postures
from .loads import JointLoads, load_arrays
from .manikin import strengths, working_area
from .options import ErgoOptions
from .owas import owas
from .reba import reba
from .rula import rula
from .worksheet import worksheet

SOURCES = {
    "joint_loads": "Delfs 2012 eq. 3.11 (moments of gravity, contacts and loads over each joint's subtree)",
    "strength": "solver/body/humans/anthropometry.py: Anderson et al. 2007 (hip, knee, ankle); one trained subject "
    "(rbdl data) for shoulder, elbow, wrist, lumbar flexion/extension; other joints estimates",
    "l4_l5": "estimate: single equivalent muscle, 5 cm moment arm (Chaffin, Andersson & Martin, Occupational "
    "Biomechanics); limits 3400 / 6400 N (NIOSH 1981)",
    "rula": "McAtamney & Corlett 1993, Appl. Ergon. 24(2):91-99",
    "reba": "Hignett & McAtamney 2000, Appl. Ergon. 31:201-205",
    "owas": "Karhu, Kansi & Kuorinka 1977, Appl. Ergon. 8(4):199-201; action categories transcribed from "
    "github.com/rs9000/ergonomics (disputed cells flagged)",
    "niosh": "Waters et al. 1993; NIOSH Applications Manual for the Revised Lifting Equation, Pub. 94-110",
    "worksheet": "Delfs 2012 §5.4 / fig. 5.2 (SES); thresholds ISO 11226, EN 1005-4, NIOSH 1981, project defaults",
    "working_area": "Delfs 2012 §6.1.2 workspace box from the manikin's zero pose",
}


_PLAIN = (str, int, bool, type(None))  # JSON values clean keeps as they are


def clean(value):
    """JSON-safe copy: numpy scalars to Python, non-finite floats to None."""
    kind = type(value)
    if kind is float:  # the common cases first, by exact type: a long motion cleans millions of values
        return value if math.isfinite(value) else None
    if kind is dict:
        return {k if type(k) is str else str(k): clean(v) for k, v in value.items()}
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


def frame_report(f: Frame, options: ErgoOptions, model: Model | None, area, lift: dict | None) -> tuple[dict, str]:
    """The ergonomics of one frame (JSON-safe) and where its joint strengths came from. ``area``: the working
    area of ``model`` (or None); ``lift``: the motion's NIOSH lift (:func:`niosh.lift`), whose D and FM every
    frame's NIOSH values use (None: the frame's ``niosh`` is left out, for :func:`niosh.at_point` later)."""
    report, loads, strength_note = frame_parts(f, options, model, area, lift)
    report["joint_loads"] = loads.as_dict()
    return report, strength_note


def frame_parts(
    f: Frame, options: ErgoOptions, model: Model | None, area, lift: dict | None
) -> tuple[dict, JointLoads, str]:
    """:func:`frame_report` with its ``joint_loads`` (None in the report) as arrays, their ``l4_l5`` JSON-safe: the
    report, the loads, where the strengths came from. A long motion writes the loads as text from the arrays
    (:mod:`.report_text`) without building a dict per joint."""
    strength, strength_note = strengths(f, model)
    loads = load_arrays(f, strength)
    posture = postures.measure(f)
    load_kg = options.load_mass if options.load_mass is not None else niosh.hand_load_kg(f)
    report = dict(
        frame=f.number,
        converged=f.converged,
        status=f.status(),
        posture=posture if "reason" in posture else postures.rounded(posture),
        joint_loads=None,  # JSON-safe already (JointLoads.as_dict): not walked by clean, the bulk of a frame's values
        rula=rula(posture, load_kg, options),
        reba=reba(posture, load_kg, options),
        owas=owas(f, posture, load_kg),
        worksheet=worksheet(f, posture, loads.percent, loads.l4_l5, area),
    )
    if lift is not None:
        report["niosh"] = niosh.at_point(niosh.hand_point(f), lift, options.coupling)
    loads.l4_l5 = clean(loads.l4_l5)
    return clean(report), loads, strength_note


def report_head(
    options: ErgoOptions,
    model_note: str,
    strength_note: str,
    area,
    lift: dict,
    result: str | None = None,
    scenario: str | None = None,
) -> dict:
    """The report's entries other than its frames (see :func:`evaluate_frames`), JSON-safe."""
    return clean(
        dict(
            result=result,
            scenario=scenario,
            manikin=model_note,
            strength=strength_note,
            working_area=area.as_dict() if area is not None else None,
            options=asdict(options),
            sources=SOURCES,
            niosh=lift,
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
    lift = niosh.lift(frames, options)
    out, strength_note = [], ""
    for f in frames:
        report, strength_note = frame_report(f, options, model, area, lift)
        out.append(report)
    return report_head(options, model_note, strength_note, area, lift, result, scenario) | dict(
        frames=out,
        not_converged=[f.number for f in frames if f.converged is False],
        not_held=[f.number for f in frames if f.broken],
    )


def write_json(report: dict, path: Path) -> None:
    """The report as JSON (no NaN: :func:`clean` made them null)."""
    write_file(path, report, allow_nan=False)


def _get(d: dict | None, *keys):
    for k in keys:
        if not isinstance(d, dict):
            return None
        d = d.get(k)
    return d


ANGLES = [("trunk_flexion",), ("trunk_side_bend",), ("trunk_twist",), ("neck_flexion",), ("head_tilt",)]
ANGLES += [(s, k) for s in ("l", "r") for k in ("upper_arm_elevation", "elbow_flexion", "knee_flexion")]


def csv_header(items: list[str], joints: list[str]) -> list[str]:
    """The CSV's columns for the worksheet ``items`` and the ``joints`` whose percent of strength is shown."""
    header = ["frame", "converged", "status", "rula", "reba", "reba_risk", "owas_code", "owas_category"]
    header += ["_".join(a) if len(a) == 1 else f"{a[1]}_{a[0]}" for a in ANGLES]
    header += ["l4_l5_flexion_moment_Nm", "l4_l5_compression_N", "worst_joint", "worst_percent"]
    header += [f"ws_{k}" for k in items] + ["ws_overall", "niosh_H_cm", "niosh_V_cm", "niosh_A_deg", "niosh_RWL_kg"]
    return header + [f"pct_{j}" for j in joints]


def csv_row(f: dict, items: list[str], joints: list[str]) -> list:
    """One frame's row (as :func:`csv_header`), from its report."""
    ws = f["worksheet"]
    strength = ws.get("joint_strength", {})
    row = [f["frame"], f["converged"], f.get("status"), f["rula"]["score"], f["reba"]["score"],
           f["reba"].get("risk"), f["owas"].get("code"), f["owas"].get("action_category")]  # fmt: skip
    row += [_get(f["posture"], *a) for a in ANGLES]
    l45 = f["joint_loads"]["l4_l5"]
    row += [l45.get("flexion_moment"), l45.get("compression"), strength.get("joint"), strength.get("value")]
    row += [ws[k]["level"] for k in items] + [ws["overall"]]
    row += [_get(f["niosh"], k) for k in ("H", "V", "A", "RWL")]
    return row + [f["joint_loads"][j]["percent_strength"] for j in joints]


def csv_cells(row: list) -> list:
    """A row as written: None empty, floats rounded to 4 decimals."""
    return ["" if v is None else round(v, 4) if isinstance(v, float) else v for v in row]


def worksheet_items(f: dict) -> list[str]:
    """The worksheet items of a frame's report (its CSV columns)."""
    return [k for k in f["worksheet"] if k != "overall"]


def csv_rows(report: dict) -> tuple[list[str], list[list]]:
    """Header and rows: one row per frame with scores, body angles, L4/L5, worksheet levels, NIOSH and the
    percent of strength of every joint that has a strength."""
    frames = report["frames"]
    items = worksheet_items(frames[0]) if frames else []
    joints = [
        j for j in (frames[0]["joint_loads"] if frames else {})
        if j != "l4_l5" and any(f["joint_loads"][j]["percent_strength"] is not None for f in frames)
    ]  # fmt: skip
    return csv_header(items, joints), [csv_row(f, items, joints) for f in frames]


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
    """What ``ergo`` prints: a line per frame (the first and last of a long motion), the frames that did not
    converge, the NIOSH lift and the files written. ``report``: what :func:`solver.ergonomics.run` returns (its
    ``frames`` are the ones shown; ``frame_count`` and ``highest_reba`` cover them all) or a whole report."""
    frames = report["frames"]
    count = report.get("frame_count", len(frames))
    shown = frames if len(frames) <= 10 else [frames[0], frames[-1]]
    lines = []
    for f in shown:
        c = f["joint_loads"]["l4_l5"].get("compression")
        broken = str(f.get("status", "")).startswith("NOT held")
        disc = "n/a" if c is None else ("not physical" if broken else f"{c:.0f} N")
        flag = "" if f["converged"] is not False else f"  [NOT converged: {f['status']}]"
        lines.append(f"frame {f['frame']}: RULA {f['rula']['score']}, REBA {f['reba']['score']}, "
                     f"OWAS {f['owas'].get('code')}, L4/L5 {disc}, worksheet {f['worksheet']['overall']}"
                     + flag)  # fmt: skip
    missed, held = report.get("not_converged", []), report.get("not_held", [])
    if count > len(shown):
        worst = report.get("highest_reba") or max(frames, key=lambda f: f["reba"]["score"] or 0)
        lines.append(f"... {count} frames; highest REBA {worst['reba']['score']} at frame {worst['frame']}"
                     + (" (of the converged frames)" if missed and len(missed) < count else ""))  # fmt: skip
    if missed:
        lines.append(f"NOT converged: {len(missed)} of {count} frames {_frame_list(missed)}; their scores "
                     f"describe the solver's closest pose" + (f"; supports or balance NOT held in "
                     f"{_frame_list(held)}: loads there are not physical" if held else ""))  # fmt: skip
    lift = report["niosh"]
    if lift.get("LI") is not None:
        lines.append(f"NIOSH lift: RWL {lift['RWL']:.1f} kg, load {lift['load_kg']:.1f} kg, LI {lift['LI']:.2f}")
    lines.append("wrote " + ", ".join(report["written"]))
    return lines


def _frame_list(numbers: list[int], shown: int = 8) -> str:
    text = ", ".join(map(str, numbers[:shown]))
    return f"[{text}{', ...' if len(numbers) > shown else ''}]"
