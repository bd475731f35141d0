"""The evaluation of a whole result file and its outputs: per-frame JSON and a CSV with one row per frame."""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path

import numpy as np

from ..io.files import open_output
from ..io.files import write_json as write_file
from ..io.frame import Frame
from ..model import Model
from . import niosh, postures
from .loads import joint_loads
from .manikin import strengths, working_area
from .options import ErgoOptions
from .owas import owas
from .reba import reba
from .rula import rula
from .worksheet import worksheet

SOURCES = {
    "joint_loads": "Delfs 2012 eq. 3.11 (moments of gravity, contacts and loads over each joint's subtree)",
    "strength": "solver/bodies/anthropometry.py: Anderson et al. 2007 (hip, knee, ankle); one trained subject "
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


def clean(value):
    """JSON-safe copy: numpy scalars to Python, non-finite floats to None."""
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
    d = lift["origin"]["D"] if "origin" in lift else 25.0
    fm = lift["origin"]["FM"] if "origin" in lift else 1.0
    strength_note = ""
    out = []
    for f in frames:
        strength, strength_note = strengths(f, model)
        loads, _, percent = joint_loads(f, strength)
        posture = postures.measure(f)
        load_kg = options.load_mass if options.load_mass is not None else niosh.hand_load_kg(f)
        out.append(
            dict(
                frame=f.number,
                converged=f.converged,
                status=f.status(),
                posture=posture if "reason" in posture else postures.rounded(posture),
                joint_loads=loads,
                rula=rula(posture, load_kg, options),
                reba=reba(posture, load_kg, options),
                owas=owas(f, posture, load_kg),
                worksheet=worksheet(f, posture, percent, loads["l4_l5"], area),
                niosh=niosh.at_frame(f, d, fm, options.coupling),
            )
        )
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
            not_converged=[f.number for f in frames if f.converged is False],
            not_held=[f.number for f in frames if f.broken],
            frames=out,
        )
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


def csv_rows(report: dict) -> tuple[list[str], list[list]]:
    """Header and rows: one row per frame with scores, body angles, L4/L5, worksheet levels, NIOSH and the
    percent of strength of every joint that has a strength."""
    frames = report["frames"]
    items = [k for k in (frames[0]["worksheet"] if frames else {}) if k != "overall"]
    joints = [
        j for j in (frames[0]["joint_loads"] if frames else {})
        if j != "l4_l5" and any(f["joint_loads"][j]["percent_strength"] is not None for f in frames)
    ]  # fmt: skip
    angles = [("trunk_flexion",), ("trunk_side_bend",), ("trunk_twist",), ("neck_flexion",), ("head_tilt",)]
    angles += [(s, k) for s in ("l", "r") for k in ("upper_arm_elevation", "elbow_flexion", "knee_flexion")]
    header = ["frame", "converged", "status", "rula", "reba", "reba_risk", "owas_code", "owas_category"]
    header += ["_".join(a) if len(a) == 1 else f"{a[1]}_{a[0]}" for a in angles]
    header += ["l4_l5_flexion_moment_Nm", "l4_l5_compression_N", "worst_joint", "worst_percent"]
    header += [f"ws_{k}" for k in items] + ["ws_overall", "niosh_H_cm", "niosh_V_cm", "niosh_A_deg", "niosh_RWL_kg"]
    header += [f"pct_{j}" for j in joints]
    rows = []
    for f in frames:
        ws = f["worksheet"]
        strength = ws.get("joint_strength", {})
        row = [f["frame"], f["converged"], f.get("status"), f["rula"]["score"], f["reba"]["score"],
               f["reba"].get("risk"), f["owas"].get("code"), f["owas"].get("action_category")]  # fmt: skip
        row += [_get(f["posture"], *a) for a in angles]
        l45 = f["joint_loads"]["l4_l5"]
        row += [l45.get("flexion_moment"), l45.get("compression"), strength.get("joint"), strength.get("value")]
        row += [ws[k]["level"] for k in items] + [ws["overall"]]
        row += [_get(f["niosh"], k) for k in ("H", "V", "A", "RWL")]
        row += [f["joint_loads"][j]["percent_strength"] for j in joints]
        rows.append(row)
    return header, rows


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
            w.writerow(["" if v is None else round(v, 4) if isinstance(v, float) else v for v in row])


def summary_lines(report: dict) -> list[str]:
    """What ``ergo`` prints: a line per frame (the first and last of a long motion), the frames that did not
    converge, the NIOSH lift and the files written."""
    frames = report["frames"]
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
    if len(frames) > len(shown):
        trusted = [f for f in frames if f["converged"] is not False] or frames
        worst = max(trusted, key=lambda f: f["reba"]["score"] or 0)
        lines.append(f"... {len(frames)} frames; highest REBA {worst['reba']['score']} at frame {worst['frame']}"
                     + (" (of the converged frames)" if len(trusted) < len(frames) else ""))  # fmt: skip
    missed, held = report.get("not_converged", []), report.get("not_held", [])
    if missed:
        lines.append(f"NOT converged: {len(missed)} of {len(frames)} frames {_frame_list(missed)}; their scores "
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
