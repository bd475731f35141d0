"""A picture of an envelope (matplotlib, PNG): its sections through the shoulder, sagittal, transverse and frontal,
in balance and without it, with the arm's own reach as a circle. Distances in m; forward (the manikin's -y) points
to the right in the side and top views."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..io.files import open_output
from .analysis import mesh, section
from .sweep import Envelope

STYLE = {
    "balanced": ("#1f8a4c", "-", "in balance"),
    "kinematic": ("#777777", "--", "without balance"),
    "planted": ("#c06a1a", "-.", "in balance, feet planted"),
}  # the last only when stepping
# (title, plane normal, horizontal axis (world vector, label), vertical axis): each panel's view
VIEWS = (
    ("side (sagittal)", (1.0, 0.0, 0.0), ((0.0, -1.0, 0.0), "forward (m)"), ((0.0, 0.0, 1.0), "height (m)")),
    ("top (transverse)", (0.0, 0.0, 1.0), ((0.0, -1.0, 0.0), "forward (m)"), ((1.0, 0.0, 0.0), "to the left (m)")),
    ("front (frontal)", (0.0, 1.0, 0.0), ((-1.0, 0.0, 0.0), "to the right (m)"), ((0.0, 0.0, 1.0), "height (m)")),
)


def plot_envelope(envelope: Envelope, path: str | Path, stats: dict | None = None) -> Path:
    """Write the sections of ``envelope`` as a PNG at ``path``; the path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    fig, axes = plt.subplots(1, 3, figsize=(13.5, 5.0))
    meshes = {which: mesh(envelope, which) for which in envelope.kinds()}
    s = envelope.shoulder
    circle = np.linspace(0.0, 2.0 * np.pi, 181)
    for ax, (title, normal, (hx, hlabel), (vx, vlabel)) in zip(axes, VIEWS, strict=True):
        h_axis, v_axis = np.array(hx), np.array(vx)
        for which, m in meshes.items():
            colour, dash, label = STYLE[which]
            if which == "balanced" and envelope.feet != "planted":
                label += ", stepping"
            segments = section(m.vertices, m.faces, s, np.array(normal))
            flat = np.stack([segments @ h_axis, segments @ v_axis], axis=-1)
            ax.add_collection(LineCollection(flat, colors=colour, linestyles=dash, linewidths=2.0, label=label))
        ring_h = s @ h_axis + envelope.arm * np.cos(circle)
        ring_v = s @ v_axis + envelope.arm * np.sin(circle)
        ax.plot(ring_h, ring_v, ":", color="#3060c0", linewidth=1.2, label="arm alone")
        ax.plot([s @ h_axis], [s @ v_axis], "o", color="black", markersize=4)
        if v_axis[2] == 1.0:
            ax.axhline(0.0, color="#b08040", linewidth=1.0)  # the floor
        ax.set_title(title)
        ax.set_xlabel(hlabel)
        ax.set_ylabel(vlabel)
        ax.set_aspect("equal")
        ax.autoscale_view()
        ax.grid(True, linewidth=0.3)
    axes[0].legend(loc="lower left", fontsize=8)
    feet = "feet planted" if envelope.feet == "planted" else "stepping"
    head = f"{envelope.manikin}: reach of the {envelope.side} hand, load {envelope.load_kg:g} kg, {feet}"
    if stats is not None:
        o = stats["overall"]
        head += (f"; balance takes off {o['mean_difference_m'] * 1e3:.0f} mm on average, "
                 f"at most {o['max_difference_m'] * 1e3:.0f} mm")  # fmt: skip
    fig.suptitle(head, fontsize=11)
    fig.tight_layout()
    try:
        with open_output(path, binary=True) as fh:  # a full disk: one line naming the file, no half a PNG
            fig.savefig(fh, format="png", dpi=80)
    finally:
        plt.close(fig)
    return Path(path)
