"""The pictures of a job's driving frames (matplotlib, Agg, PNG bytes): the manikin as a stick figure in a side
view and a front view (:mod:`solver.sketch`), the floor, and each lever arm a method rates (from its joint to the
hands: the horizontal distance as a solid line, the drop to the hands dotted, its length written)."""

from __future__ import annotations

import io
import textwrap

import numpy as np

from ..io.result.frame import Frame
from ..sketch import VIEWS, draw_points, draw_segments, project

BODY, LEVER = "#333333", "#c62828"


def body_segments(frame: Frame) -> list[tuple[np.ndarray, np.ndarray]]:
    """The frame's bones: each link's joint to its parent link's joint, each TCP (hands, head, feet) to its link's
    joint; the root's translations left out (they start at the world origin). World m."""
    link_joint = {int(link): i for i, link in enumerate(frame.joint_link)}
    pos, prism = frame.joint_position, frame.prismatic
    out = []
    for link, parent in enumerate(frame.link_parent):
        i, j = link_joint.get(link), link_joint.get(int(parent))
        if i is not None and j is not None and not (prism[i] or prism[j]):
            out.append((pos[j], pos[i]))
    for name, link in frame.tcp_link.items():
        if link_joint.get(link) is not None:
            out.append((pos[link_joint[link]], frame.tcp_position[name]))
    return out


def lever_segments(lever: dict, down: np.ndarray) -> tuple[tuple, tuple, np.ndarray]:
    """A lever arm ``lever`` (``origin``, ``end``: world m) as its horizontal part (origin to above/below the end,
    across gravity ``down``), its vertical part (to the end) and the middle of the horizontal part."""
    origin, end = np.asarray(lever["origin"], float), np.asarray(lever["end"], float)
    d = end - origin
    corner = end - np.dot(d, down) * down  # the end moved along gravity to the origin's height
    return (origin, corner), (corner, end), (origin + corner) / 2.0


def frame_png(frame: Frame, title: str, levers: list[dict]) -> bytes:
    """Side and front view of ``frame`` with ``levers`` (dicts with origin, end, length_m, label); PNG bytes."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    down = frame.gravity / np.linalg.norm(frame.gravity)
    bones = body_segments(frame)
    fig, axes = plt.subplots(1, 2, figsize=(5.6, 3.2))
    for ax, view in zip(axes, ("side", "front"), strict=True):
        draw_segments(ax, bones, view, BODY, linewidth=1.2)
        ax.axhline(0.0, color="#b08040", linewidth=1.0)  # the floor
        for lever in levers:
            flat, drop, middle = lever_segments(lever, down)
            draw_segments(ax, [flat], view, LEVER, linewidth=2.0)
            draw_segments(ax, [drop], view, LEVER, linestyle=":", linewidth=1.2)
            draw_points(ax, [lever["origin"], lever["end"]], view, LEVER, size=4.0)
            x, y = project([middle], view)[0]
            ax.annotate(f"{lever['length_m']:.2f} m", (x, y), textcoords="offset points", xytext=(0, 4),
                        ha="center", fontsize=7, color=LEVER)  # fmt: skip
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(f"{view} view", fontsize=8)
        ax.set_xlabel(VIEWS[view][2], fontsize=7)
        ax.tick_params(labelsize=6)
    axes[0].set_ylabel("height (m)", fontsize=7)
    fig.suptitle(textwrap.fill(title, 90), fontsize=7)
    fig.tight_layout()
    buf = io.BytesIO()
    try:
        fig.savefig(buf, format="png", dpi=80)
    finally:
        plt.close(fig)
    return buf.getvalue()
