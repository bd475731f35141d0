"""An envelope's files in an output folder, ``<manikin>_<hand>`` + ``.csv`` (per direction: reach in balance,
without it, the arm's), ``.obj`` and ``.glb`` (both meshes), ``.png`` (sections); and ``envelopes.csv``, one row per
manikin and hand (volumes, mean and largest differences), rewritten after each so that an interrupted run keeps
every finished envelope. Units: m, m^3, kg, s."""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np

from ..io.files import open_output, write_texts
from .analysis import angles, envelope_file, sectors
from .mesh_files import glb_bytes, obj_text
from .sweep import Envelope

SUMMARY = "envelopes.csv"
DIRECTION_COLUMNS = ("manikin", "hand", "load_kg", "direction", "dx", "dy", "dz", "azimuth_deg", "elevation_deg",
                     "sector", "reach_balanced_m", "reach_kinematic_m", "arm_length_m", "difference_m")  # fmt: skip
SUMMARY_COLUMNS = ("manikin", "hand", "load_kg", "directions", "balanced_mean_m", "kinematic_mean_m",
                   "arm_length_m", "mean_difference_m", "max_difference_m", "worst_sector", "front_low_difference_m",
                   "volume_balanced_m3", "volume_kinematic_m3", "volume_lost", "unreached", "solves",
                   "time_s")  # fmt: skip


def stem(envelope: Envelope) -> str:
    """The file name stem of an envelope: ``<manikin>_<hand>``."""
    return f"{envelope.manikin}_{envelope.side}"


def _csv(columns: tuple[str, ...], rows: list[dict]) -> str:
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return out.getvalue()


def direction_rows(envelope: Envelope) -> list[dict]:
    """One row per direction: its unit vector, angles, sector and the three reaches (m)."""
    d = envelope.sphere.directions
    azimuth, elevation = angles(d)
    names = sectors(d, envelope.side)
    rows = []
    for i in range(len(d)):
        bal, kin = float(envelope.balanced[i]), float(envelope.kinematic[i])
        rows.append({
            "manikin": envelope.manikin, "hand": envelope.side, "load_kg": envelope.load_kg, "direction": i,
            "dx": round(float(d[i, 0]), 6), "dy": round(float(d[i, 1]), 6), "dz": round(float(d[i, 2]), 6),
            "azimuth_deg": round(float(azimuth[i]), 2), "elevation_deg": round(float(elevation[i]), 2),
            "sector": names[i], "reach_balanced_m": round(bal, 4), "reach_kinematic_m": round(kin, 4),
            "arm_length_m": round(envelope.arm, 4), "difference_m": round(kin - bal, 4),
        })  # fmt: skip
    return rows


def summary_row(envelope: Envelope, stats: dict) -> dict:
    """The ``envelopes.csv`` row of one envelope."""
    o, vol = stats["overall"], stats["volume_m3"]
    front_low = stats["sectors"].get("front-low", {}).get("mean_difference_m", np.nan)
    return {
        "manikin": envelope.manikin, "hand": envelope.side, "load_kg": envelope.load_kg,
        "directions": o["directions"], "balanced_mean_m": round(o["balanced_mean_m"], 4),
        "kinematic_mean_m": round(o["kinematic_mean_m"], 4), "arm_length_m": round(envelope.arm, 4),
        "mean_difference_m": round(o["mean_difference_m"], 4), "max_difference_m": round(o["max_difference_m"], 4),
        "worst_sector": stats["worst_sector"], "front_low_difference_m": round(float(front_low), 4),
        "volume_balanced_m3": round(vol["balanced"], 4), "volume_kinematic_m3": round(vol["kinematic"], 4),
        "volume_lost": round(stats["volume_lost"], 4), "unreached": stats["unreached"], "solves": envelope.tests,
        "time_s": round(envelope.time_s, 2),
    }  # fmt: skip


def write_envelope(envelope: Envelope, stats: dict, folder: Path, plot: bool = True) -> list[Path]:
    """Write one envelope's CSV, OBJ, GLB (and PNG) into ``folder``; the paths written."""
    base = folder / stem(envelope)
    meshes = envelope_file(envelope)
    written = write_texts([(base.with_suffix(".csv"), _csv(DIRECTION_COLUMNS, direction_rows(envelope))),
                           (base.with_suffix(".obj"), obj_text(meshes))])  # fmt: skip
    with open_output(base.with_suffix(".glb"), binary=True) as out:
        out.write(glb_bytes(meshes))
    written.append(base.with_suffix(".glb"))
    if plot:
        from .plot import plot_envelope

        written.append(plot_envelope(envelope, base.with_suffix(".png"), stats))
    return written


def write_summary(rows: list[dict], folder: Path) -> Path:
    """Write ``envelopes.csv`` (one row per envelope so far) into ``folder``."""
    return write_texts([(folder / SUMMARY, _csv(SUMMARY_COLUMNS, rows))])[0]
