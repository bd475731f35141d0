"""An envelope's files in an output folder, ``<manikin>_<hand>`` + ``.csv`` (per direction: reach in balance,
without it, the arm's), ``.obj`` and ``.glb`` (its meshes), ``.png`` (sections); and ``envelopes.csv``, one row per
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
DIRECTION_COLUMNS = ("manikin", "hand", "load_kg", "feet", "direction", "dx", "dy", "dz", "azimuth_deg",
                     "elevation_deg", "sector", "reach_balanced_m", "reach_kinematic_m", "reach_planted_m",
                     "arm_length_m", "difference_m")  # fmt: skip
SETTING_COLUMNS = ("manikin", "hand", "load_kg", "feet", "sole_scale")  # what the envelope was asked for
RESULT_COLUMNS = ("directions", "balanced_mean_m", "balanced_min_m", "balanced_max_m", "kinematic_mean_m",
                  "arm_length_m", "mean_difference_m", "max_difference_m", "worst_sector", "front_low_difference_m",
                  "volume_balanced_m3", "volume_kinematic_m3", "volume_lost", "planted_mean_m", "stepping_gain_m",
                  "stepping_gain_max_m", "volume_planted_m3", "unreached", "solves", "time_s")  # fmt: skip
SUMMARY_COLUMNS = SETTING_COLUMNS + RESULT_COLUMNS


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
        planted = None if envelope.planted is None else round(float(envelope.planted[i]), 4)
        rows.append({
            "manikin": envelope.manikin, "hand": envelope.side, "load_kg": envelope.load_kg, "feet": envelope.feet,
            "direction": i, "reach_planted_m": planted,
            "dx": round(float(d[i, 0]), 6), "dy": round(float(d[i, 1]), 6), "dz": round(float(d[i, 2]), 6),
            "azimuth_deg": round(float(azimuth[i]), 2), "elevation_deg": round(float(elevation[i]), 2),
            "sector": names[i], "reach_balanced_m": round(bal, 4), "reach_kinematic_m": round(kin, 4),
            "arm_length_m": round(envelope.arm, 4), "difference_m": round(kin - bal, 4),
        })  # fmt: skip
    return rows


def summary_row(envelope: Envelope, stats: dict) -> dict:
    """The ``envelopes.csv`` row of one envelope (SUMMARY_COLUMNS; the stepping columns None with planted feet)."""
    o, vol, step = stats["overall"], stats["volume_m3"], stats["stepping"] or {}
    front_low = stats["sectors"].get("front-low", {}).get("mean_difference_m", np.nan)
    stepping = {"planted_mean_m": step.get("planted_mean_m"), "stepping_gain_m": step.get("gain_mean_m"),
                "stepping_gain_max_m": step.get("gain_max_m"), "volume_planted_m3": vol.get("planted")}  # fmt: skip
    return {
        "manikin": envelope.manikin, "hand": envelope.side, "load_kg": envelope.load_kg, "feet": envelope.feet,
        "sole_scale": envelope.sole_scale,
        "directions": o["directions"], "balanced_mean_m": round(o["balanced_mean_m"], 4),
        "balanced_min_m": round(o["balanced_min_m"], 4), "balanced_max_m": round(o["balanced_max_m"], 4),
        "kinematic_mean_m": round(o["kinematic_mean_m"], 4), "arm_length_m": round(envelope.arm, 4),
        "mean_difference_m": round(o["mean_difference_m"], 4), "max_difference_m": round(o["max_difference_m"], 4),
        "worst_sector": stats["worst_sector"], "front_low_difference_m": round(float(front_low), 4),
        "volume_balanced_m3": round(vol["balanced"], 4), "volume_kinematic_m3": round(vol["kinematic"], 4),
        "volume_lost": round(stats["volume_lost"], 4), "unreached": stats["unreached"], "solves": envelope.tests,
        "time_s": round(envelope.time_s, 2),
    } | {key: None if value is None else round(value, 4) for key, value in stepping.items()}  # fmt: skip


def write_envelope(envelope: Envelope, stats: dict, folder: Path, plot: bool = True, name: str | None = None
                   ) -> list[Path]:  # fmt: skip
    """Write one envelope's CSV, OBJ, GLB (and PNG) into ``folder``, named ``name`` (default :func:`stem`) + the
    suffix; the paths written."""
    base = name or stem(envelope)
    path = {suffix: folder / f"{base}.{suffix}" for suffix in ("csv", "obj", "glb", "png")}  # a name may hold a "."
    meshes = envelope_file(envelope)
    written = write_texts([(path["csv"], _csv(DIRECTION_COLUMNS, direction_rows(envelope))),
                           (path["obj"], obj_text(meshes))])  # fmt: skip
    with open_output(path["glb"], binary=True) as out:
        out.write(glb_bytes(meshes))
    written.append(path["glb"])
    if plot:
        from .plot import plot_envelope

        written.append(plot_envelope(envelope, path["png"], stats))
    return written


def write_summary(rows: list[dict], folder: Path) -> Path:
    """Write ``envelopes.csv`` (one row per envelope so far) into ``folder``."""
    return write_texts([(folder / SUMMARY, _csv(SUMMARY_COLUMNS, rows))])[0]
