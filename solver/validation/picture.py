"""The picture of a validation run (matplotlib, PNG): per key frame, the measured skeleton and the predicted one
side by side, seen from the subject's right (forward to the right), the floor drawn."""

from __future__ import annotations

import math
from pathlib import Path

from ..sketch import draw_points, draw_segments
from .skeleton import BONES

GAP = 0.9  # m between the measured skeleton and the predicted one in each panel
COLOURS = {"measured": "#222222", "predicted": "#c06a1a"}


def _draw(ax, points: dict, shift: float, colour: str) -> None:
    """One skeleton in side view: forward (-y) to the right, shifted by ``shift`` (m)."""
    draw_segments(ax, [(points[a], points[b]) for a, b in BONES], "side", colour, shift)
    draw_points(ax, [points[n] for n in ("wrist_r", "wrist_l")], "side", colour, shift)


def draw(report: dict, path: str | Path) -> Path:
    """Write the side-by-side skeletons of every key frame of ``report`` to ``path`` (PNG); the path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = report["rows"]
    cols = min(4, len(rows))
    lines = math.ceil(len(rows) / cols)
    fig, axes = plt.subplots(lines, cols, figsize=(3.6 * cols, 3.4 * lines), squeeze=False)
    for ax in axes.flat[len(rows) :]:
        ax.axis("off")
    for ax, r in zip(axes.flat, rows, strict=False):
        _draw(ax, r["skeletons"]["measured"], 0.0, COLOURS["measured"])
        _draw(ax, r["skeletons"]["predicted"], GAP, COLOURS["predicted"])
        ax.axhline(0.0, color="#b08040", linewidth=1.0)
        verdict = "" if r["converged"] else " (NOT converged)"
        ax.set_title(f"{r['name']}{verdict}\n{r['task']}, {r['style']}", fontsize=8)
        ax.set_aspect("equal")
        ax.set_xlim(-0.7, GAP + 0.8)
        ax.set_ylim(-0.05, 2.0)
        ax.tick_params(labelsize=6)
    axes.flat[0].plot([], [], color=COLOURS["measured"], label="measured (CMU)")
    axes.flat[0].plot([], [], color=COLOURS["predicted"], label="predicted (Manikin)")
    axes.flat[0].legend(loc="upper left", fontsize=6)
    fig.suptitle("Measured (left) and predicted (right) postures, side view, forward to the right (m)", fontsize=9)
    fig.tight_layout(rect=(0.0, 0.0, 1.0, 0.97))  # room for the title
    path = Path(path)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path
