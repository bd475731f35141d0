"""PNG plots of an ergonomics report (matplotlib figures without pyplot, so no global backend is chosen: the same
code runs inside Blender, where other add-ons may use matplotlib too): joint loads, the scores with plot bands
(RULA, REBA: :attr:`.base.Score.bands`), back and arms.

Over time (one point per frame) for a motion; bar charts for a single pose. Colours follow the worksheet:
green / yellow / red bands with the thresholds of :mod:`.worksheet`.
"""

from __future__ import annotations

from pathlib import Path

from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from ..io.files import open_output
from .registry import frame_scores
from .report import plot_paths
from .worksheet import STRENGTH_BANDS

GREEN, YELLOW, RED = "#cfe8cf", "#fbeeb8", "#f6c9c4"
LEVEL_COLOUR = {"green": "#3a9a3a", "yellow": "#d9a400", "red": "#c8372d", None: "#888888"}
TOP_JOINTS = 8


def _bands(ax, edges: list[float], horizontal: bool = True) -> None:
    """Shade green / yellow / red between consecutive edges (value axis)."""
    for lo, hi, colour in zip(edges[:-1], edges[1:], (GREEN, YELLOW, RED), strict=False):
        (ax.axhspan if horizontal else ax.axvspan)(lo, hi, color=colour, zorder=0, lw=0)


def _marker(x: list) -> str | None:
    """Dots on short motions only; long ones read better as plain lines."""
    return "o" if len(x) <= 30 else None


def _worst_joints(frames: list[dict]) -> list[str]:
    peak: dict[str, float] = {}
    for f in frames:
        for name, load in f["joint_loads"].items():
            p = load.get("percent_strength")
            if name != "l4_l5" and p is not None:
                peak[name] = max(peak.get(name, 0.0), p)
    return sorted(peak, key=peak.get, reverse=True)[:TOP_JOINTS]


def plot_loads(report: dict, path: Path) -> Path:
    frames = report["frames"]
    x = [f["frame"] for f in frames]
    joints = _worst_joints(frames)
    comp = [f["joint_loads"]["l4_l5"].get("compression") for f in frames]
    fig = Figure(figsize=(12, 5))
    ax1, ax2 = fig.subplots(1, 2, gridspec_kw={"width_ratios": [2.2, 1]})
    g, y = STRENGTH_BANDS
    top = max([y * 1.5] + [f["joint_loads"][j]["percent_strength"] or 0 for f in frames for j in joints]) * 1.1
    if len(frames) == 1:
        vals = [frames[0]["joint_loads"][j]["percent_strength"] for j in joints][::-1]
        _bands(ax1, [0, g, y, top], horizontal=False)
        ax1.barh(joints[::-1], vals, color="#4a6fa5", zorder=2)
        for i, v in enumerate(vals):
            ax1.text(v + top * 0.01, i, f"{v:.0f} %", va="center", fontsize=9, zorder=3)
        ax1.set_xlim(0, top)
        ax1.set_xlabel("percent of joint strength")
    else:
        _bands(ax1, [0, g, y, top])
        for j in joints:
            ax1.plot(x, [f["joint_loads"][j]["percent_strength"] for f in frames], marker=_marker(x), ms=3, label=j)
        ax1.set_ylim(0, top)
        ax1.set_xlabel("frame")
        ax1.set_ylabel("percent of joint strength")
        ax1.legend(fontsize=8, loc="upper left", ncol=2)
    ax1.set_title(f"Most loaded joints (bands: {g:g} % / {y:g} %, project default)")
    if all(c is None for c in comp):
        ax2.text(0.5, 0.5, "no L4/L5 in this body", ha="center", va="center", transform=ax2.transAxes)
        ax2.set_axis_off()
    else:
        c_top = max([7500.0] + [c for c in comp if c is not None]) * 1.1
        _bands(ax2, [0, 3400, 6400, c_top])
        if len(frames) == 1:
            ax2.bar(["L4/L5"], [comp[0]], color="#4a6fa5", width=0.3, zorder=2)
            ax2.set_xlim(-0.8, 0.8)
            ax2.text(0, comp[0] + c_top * 0.01, f"{comp[0]:.0f} N", ha="center", va="bottom")
        else:
            ax2.plot(x, [c if c is not None else float("nan") for c in comp], color="#4a6fa5", marker=_marker(x), ms=3)
            ax2.set_xlabel("frame")
        ax2.set_ylim(0, c_top)
        ax2.set_ylabel("compression, N (estimate)")
        ax2.set_title("L4/L5 disc compression\n(NIOSH limits 3400 / 6400 N)")
    return _save(fig, path, report)


def plot_scores(report: dict, path: Path) -> Path:
    """A panel per score with plot bands (:attr:`.base.Score.bands`), in registration order."""
    frames = report["frames"]
    x = [f["frame"] for f in frames]
    scores = [s for s in frame_scores() if s.bands is not None]
    fig = Figure(figsize=(5.5 * max(1, len(scores)), 4.5))
    axes = fig.subplots(1, max(1, len(scores)), squeeze=False)[0]
    for ax, score in zip(axes, scores, strict=False):
        key, bands = score.name, score.bands
        values = [f[key][score.value] for f in frames]
        ax.set_title(f"{bands.title}\n({bands.legend})", fontsize=10)
        if all(s is None for s in values):
            ax.text(0.5, 0.5, frames[0][key].get("reason", "n/a"), ha="center", va="center", wrap=True,
                    transform=ax.transAxes)  # fmt: skip
            ax.set_axis_off()
            continue
        _bands(ax, list(bands.edges))
        if len(frames) == 1:
            ax.bar([score.title], values, color="#4a6fa5", width=0.3, zorder=2)
            ax.set_xlim(-0.8, 0.8)
            ax.text(0, values[0] + 0.2, str(values[0]), ha="center", va="bottom", fontsize=12)
        else:
            ax.step(x, [s if s is not None else float("nan") for s in values], where="mid", color="#4a6fa5", lw=2)
            ax.set_xlabel("frame")
        ax.set_ylim(bands.edges[0], bands.edges[-1])
        ax.set_ylabel("score")
    return _save(fig, path, report)


def plot_back(report: dict, path: Path) -> Path:
    frames = report["frames"]
    x = [f["frame"] for f in frames]
    items = [("back_bend", "trunk flexion", [0, 20, 60, 120]), ("neck", "neck flexion (to trunk)", [0, 25, 25, 90]),
             ("shoulder_l", "upper arm elevation, left", [0, 20, 60, 180]),
             ("shoulder_r", "upper arm elevation, right", [0, 20, 60, 180])]  # fmt: skip
    fig = Figure(figsize=(13, 4.2))
    axes = fig.subplots(1, len(items))
    for ax, (key, title, edges) in zip(axes, items, strict=True):
        vals = [f["worksheet"][key]["value"] for f in frames]
        ax.set_title(title, fontsize=10)
        if all(v is None for v in vals):
            ax.text(0.5, 0.5, "no human posture", ha="center", va="center", transform=ax.transAxes)
            ax.set_axis_off()
            continue
        low = min([-10.0] + [v for v in vals if v is not None])
        high = max([edges[-1]] + [v + 10 for v in vals if v is not None])
        ax.axhspan(low, 0, color=RED, zorder=0, lw=0) if key in ("back_bend", "neck") else None
        _bands(ax, edges[:-1] + [high])
        if len(frames) == 1:
            level = frames[0]["worksheet"][key]["level"]
            ax.bar([""], vals, color=LEVEL_COLOUR[level], width=0.3, zorder=2)
            ax.set_xlim(-0.8, 0.8)
            ax.text(0, vals[0] + 2, f"{vals[0]:.0f}\u00b0", ha="center", va="bottom", fontsize=12)
        else:
            ax.plot(x, [v if v is not None else float("nan") for v in vals], color="#333333", marker=_marker(x), ms=3)
            ax.set_xlabel("frame")
        ax.set_ylim(low, high)
        ax.set_ylabel("degrees")
    fig.suptitle("Back, neck and shoulders (bands: ISO 11226 / EN 1005-4)", fontsize=11)
    return _save(fig, path, report)


def _flag_unconverged(fig, report: dict) -> None:
    """Hatch the frames that did not converge on every time axis, and say so in the title: their scores describe
    the solver's best compromise (or, where priority 1 broke, a pose whose loads are not physical)."""
    frames = report["frames"]
    missed = [f["frame"] for f in frames if f.get("converged") is False]
    if not missed:
        return
    runs: list[list[int]] = []
    for n in missed:  # consecutive frames as one span
        if runs and n == runs[-1][1] + 1:
            runs[-1][1] = n
        else:
            runs.append([n, n])
    for ax in fig.axes:
        if ax.get_xlabel() == "frame":
            for lo, hi in runs:
                ax.axvspan(lo - 0.5, hi + 0.5, facecolor="none", edgecolor="#555555", hatch="//", lw=0, zorder=1)
    held = sum(1 for f in frames if f.get("converged") is False and not str(f.get("status", "")).startswith("NOT"))
    what = "1 frame" if len(frames) == 1 else f"{len(missed)} of {len(frames)} frames (hatched)"
    fig.text(0.5, 0.01, f"NOT converged: {what}; {held} with supports and balance held, "
             f"{len(missed) - held} without (loads not physical)", ha="center", va="bottom", color="#c8372d",
             fontsize=10)  # fmt: skip


def _save(fig, path: Path, report: dict) -> Path:
    for ax in fig.axes:
        if ax.get_xlabel() == "frame":
            ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    flagged = any(f.get("converged") is False for f in report["frames"])
    fig.tight_layout(rect=(0, 0.05 if flagged else 0, 1, 1))
    _flag_unconverged(fig, report)
    with open_output(path, binary=True) as fh:
        fig.savefig(fh, format="png", dpi=110)
    return path


def write_plots(report: dict, stem: Path) -> list[Path]:
    """``<stem>_loads.png``, ``<stem>_scores.png``, ``<stem>_back.png`` (:func:`.report.plot_paths`)."""
    loads, scores, back = plot_paths(stem)
    return [plot_loads(report, loads), plot_scores(report, scores), plot_back(report, back)]
