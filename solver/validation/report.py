"""The validation run written out: JSON (everything), CSV (one line per key frame and measure) and Markdown (the
summary tables the docs quote)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

from .measures import MEASURES, UNITS

FILES = ("validation.json", "validation.csv", "validation.md")


def _fmt(name: str, value: float) -> str:
    """Degrees to 0.1; the pelvis height (a fraction of stature) as a percentage of stature."""
    return f"{100.0 * value:.1f} %" if UNITS[name] != "deg" else f"{value:.1f}"


def write_json(report: dict, path: Path) -> Path:
    path.write_text(json.dumps(report, indent=1) + "\n")
    return path


def write_csv(report: dict, path: Path) -> Path:
    """One line per key frame and measure: measured, predicted, error (deg, or a fraction of stature)."""
    with path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["key_frame", "subject", "split", "task", "style", "converged", "measure", "unit", "measured",
                    "predicted", "error"])  # fmt: skip
        for r in report["rows"]:
            for name in MEASURES:
                w.writerow([r["name"], r["subject"], r["split"], r["task"], r["style"], r["converged"], name,
                            UNITS[name], f"{r['measured'][name]:.4f}", f"{r['predicted'][name]:.4f}",
                            f"{r['error'][name]:.4f}"])  # fmt: skip
    return path


def summary_table(stats: dict) -> list[str]:
    """A Markdown table: per measure, mean / median / worst absolute error and the worst key frame."""
    lines = ["| measure | mean abs error | median | worst | worst key frame |", "|---|---|---|---|---|"]
    for name in MEASURES:
        s = stats[name]
        lines.append(f"| {name} | {_fmt(name, s['mean_abs'])} | {_fmt(name, s['median_abs'])} | "
                     f"{_fmt(name, s['worst_abs'])} | {s['worst']} |")  # fmt: skip
    return lines


def markdown(report: dict) -> str:
    """The summary in Markdown: totals, per split, per task kind, then every key frame's errors."""
    s = report["summary"]
    model = report.get("model", "behaviour")
    out = [f"# Validation against motion capture (split: {report['split']}, {model} model)", "",
           f"{s['count']} key frames, {s['converged']} converged. Errors are predicted - measured; angles in deg, "
           "the pelvis height in % of stature.", "", "## All key frames", "", *summary_table(s["total"])]  # fmt: skip
    for group in ("split", "task"):
        for value, stats in s[group].items():
            out += ["", f"## {group}: {value}", "", *summary_table(stats)]
    out += ["", "## Per key frame (error)", "", "| key frame | task | style | converged | "
            + " | ".join(MEASURES) + " |", "|---" * (4 + len(MEASURES)) + "|"]  # fmt: skip
    for r in report["rows"]:
        cells = " | ".join(_fmt(n, r["error"][n]) for n in MEASURES)
        style = r["style"] + "".join(f" (heel {side} raised, planted flat)" for side in r.get("heel_raised", ()))
        out.append(f"| {r['name']} | {r['task']} | {style} | {'yes' if r['converged'] else 'NO'} | {cells} |")
    out += ["", report["citation"], ""]
    return "\n".join(out)


def write_outputs(report: dict, folder: Path, picture: bool = True) -> list[Path]:
    """JSON, CSV, Markdown (and the PNG picture) in ``folder``; the paths written."""
    folder.mkdir(parents=True, exist_ok=True)
    paths = [write_json(report, folder / FILES[0]), write_csv(report, folder / FILES[1])]
    (folder / FILES[2]).write_text(markdown(report))
    paths.append(folder / FILES[2])
    if picture:
        from .picture import draw

        paths.append(draw(report, folder / "validation.png"))
    return paths
