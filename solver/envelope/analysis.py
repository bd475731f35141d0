"""What an envelope says: its meshes, volumes, sections through the shoulder, and how much balance takes off the reach
per sector of directions. Units: m, m^3, degrees.

Sectors (seen by the manikin, which faces -y): ``up`` and ``down`` within 30 degrees of vertical; the rest by
azimuth, ``front`` / ``back`` within 45 degrees of straight ahead / behind, ``out`` to the hand's own side, ``across``
to the other, and by elevation, ``low`` (below -20 degrees), ``level`` and ``high`` (above 20 degrees).
"""

from __future__ import annotations

import numpy as np

from .mesh_files import EnvelopeFile, EnvelopeMesh
from .sweep import Envelope


def mesh(envelope: Envelope, which: str = "balanced") -> EnvelopeMesh:
    """The envelope surface: every direction at its reach (0: the shoulder), in the manikin's frame (m); ``which``
    of :meth:`Envelope.kinds`."""
    radii = envelope.radii(which)
    return EnvelopeMesh(which, envelope.shoulder + envelope.sphere.vertices(radii), envelope.sphere.faces.copy())


def envelope_file(envelope: Envelope) -> EnvelopeFile:
    """Its meshes (balanced, kinematic; planted when stepping) with the shoulder and a description of the run."""
    info = {
        "manikin": envelope.manikin, "hand": envelope.side, "load_kg": f"{envelope.load_kg:g}",
        "orientation": "free" if envelope.rotation is None else "fixed", "sole_scale": f"{envelope.sole_scale:g}",
        "feet": envelope.feet,
        "directions": str(len(envelope.sphere.directions)), "arm_length_m": f"{envelope.arm:.4f}",
    }  # fmt: skip
    return EnvelopeFile([mesh(envelope, which) for which in envelope.kinds()], envelope.shoulder.copy(), info)


def volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Enclosed volume of a closed, outward-oriented triangle mesh (m^3), by the divergence theorem."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def section(vertices: np.ndarray, faces: np.ndarray, point: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """(k, 2, 3) segments where the mesh crosses the plane through ``point`` with ``normal``; a vertex on the plane
    counts as above it, and a segment of zero length (a face touching the plane at a vertex) is left out."""
    height = (vertices - point) @ (np.asarray(normal, float) / np.linalg.norm(normal))
    segments = []
    for face in faces:
        ends = []
        for k in range(3):
            i, j = sorted((int(face[k]), int(face[(k + 1) % 3])))  # the same point from both faces of an edge
            if (height[i] < 0.0) != (height[j] < 0.0):  # the edge crosses the plane (or ends on it)
                t = height[i] / (height[i] - height[j])
                ends.append(vertices[j] if height[j] == 0.0 else vertices[i] + t * (vertices[j] - vertices[i]))
        if len(ends) == 2 and not np.array_equal(ends[0], ends[1]):
            segments.append(ends)
    return np.array(segments).reshape(-1, 2, 3)


def angles(directions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(azimuth, elevation) degrees: azimuth 0 straight ahead (-y), 90 to the manikin's left (+x)."""
    d = np.asarray(directions, float)
    azimuth = np.degrees(np.arctan2(d[:, 0], -d[:, 1]))
    elevation = np.degrees(np.arcsin(np.clip(d[:, 2], -1.0, 1.0)))
    return azimuth, elevation


def sectors(directions: np.ndarray, side: str = "right") -> list[str]:
    """The sector name of each direction (see the module's docstring) for the ``side`` hand."""
    azimuth, elevation = angles(directions)
    out = []
    for az, el in zip(azimuth, elevation, strict=True):
        if abs(el) > 60.0:
            out.append("up" if el > 0 else "down")
            continue
        if abs(az) <= 45.0:
            way = "front"
        elif abs(az) >= 135.0:
            way = "back"
        else:
            way = "out" if (az < 0) == (side == "right") else "across"
        out.append(f"{way}-{'low' if el < -20.0 else 'high' if el > 20.0 else 'level'}")
    return out


def comparison(envelope: Envelope) -> dict:
    """How much balance takes off the reach: overall and per sector, the mean and largest radial difference
    (kinematic - balanced, m) and the mean relative one; the volumes; the direction balance cuts most."""
    bal, kin = envelope.balanced, envelope.kinematic
    diff = kin - bal
    names = sectors(envelope.sphere.directions, envelope.side)
    per_sector = {}
    for name in dict.fromkeys(sorted(names)):
        pick = np.array([n == name for n in names])
        per_sector[name] = _stats(bal[pick], kin[pick])
    worst = int(np.argmax(diff))
    vol = {which: volume(m.vertices, m.faces) for which in envelope.kinds() for m in [mesh(envelope, which)]}
    return {
        "overall": _stats(bal, kin),
        "sectors": per_sector,
        "volume_m3": vol,
        "volume_lost": 1.0 - vol["balanced"] / vol["kinematic"] if vol["kinematic"] > 0 else 0.0,
        "worst_direction": envelope.sphere.directions[worst].tolist(),
        "worst_sector": names[worst],
        "unreached": int(np.sum(bal <= 0.0)),
        "stepping": None if envelope.planted is None else _stepping(envelope, names, vol),
    }


def _stepping(envelope: Envelope, names: list[str], vol: dict) -> dict:
    """What stepping adds to the planted reach (m; the volume's share): mean, largest (and its sector), least."""
    gain = envelope.balanced - envelope.planted
    return {
        "planted_mean_m": float(envelope.planted.mean()), "gain_mean_m": float(gain.mean()),
        "gain_max_m": float(gain.max()), "gain_max_sector": names[int(np.argmax(gain))],
        "gain_min_m": float(gain.min()),
        "volume_gain": vol["balanced"] / vol["planted"] - 1.0 if vol["planted"] > 0 else 0.0,
    }  # fmt: skip


def _stats(bal: np.ndarray, kin: np.ndarray) -> dict:
    diff = kin - bal
    relative = np.divide(diff, kin, out=np.zeros_like(diff), where=kin > 0)
    return {
        "directions": len(bal), "balanced_mean_m": float(bal.mean()), "kinematic_mean_m": float(kin.mean()),
        "balanced_min_m": float(bal.min()), "balanced_max_m": float(bal.max()),
        "mean_difference_m": float(diff.mean()), "max_difference_m": float(diff.max()),
        "mean_relative": float(relative.mean()),
    }  # fmt: skip


def summary_lines(envelope: Envelope, stats: dict) -> list[str]:
    """A few lines a person reads: volumes, mean and largest differences, the sectors balance cuts most."""
    o, vol = stats["overall"], stats["volume_m3"]
    lines = [
        f"{envelope.manikin} {envelope.side} hand, load {envelope.load_kg:g} kg, feet {envelope.feet}: "
        f"{o['directions']} directions, "
        f"{envelope.tests} solves in {envelope.time_s:.1f} s",
        f"  reach in balance {o['balanced_mean_m']:.3f} m mean, without balance {o['kinematic_mean_m']:.3f} m, "
        f"arm alone {envelope.arm:.3f} m",
        f"  balance takes off {o['mean_difference_m'] * 1e3:.0f} mm on average ({o['mean_relative']:.0%}), at most "
        f"{o['max_difference_m'] * 1e3:.0f} mm ({stats['worst_sector']}); volume {vol['balanced']:.2f} vs "
        f"{vol['kinematic']:.2f} m^3 (-{stats['volume_lost']:.0%})",
    ]
    ranked = sorted(stats["sectors"].items(), key=lambda kv: -kv[1]["mean_difference_m"])[:3]
    lines.append("  most cut: " + ", ".join(f"{n} {s['mean_difference_m'] * 1e3:.0f} mm" for n, s in ranked))
    step = stats["stepping"]
    if step is not None:
        lines.append(f"  stepping adds {step['gain_mean_m'] * 1e3:.0f} mm on average to the planted reach "
                     f"({step['planted_mean_m']:.3f} m), at most {step['gain_max_m'] * 1e3:.0f} mm "
                     f"({step['gain_max_sector']}); volume +{step['volume_gain']:.0%}")  # fmt: skip
    if stats["unreached"]:
        lines.append(f"  {stats['unreached']} directions not reached in balance at all")
    return lines
