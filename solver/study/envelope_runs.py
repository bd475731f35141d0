"""A study's reach-envelope runs (its ``[envelope]``): one run -> its row (in whatever process it lands in), and the
row's files, written in the study's own process as its rows come back: ``OUT/envelopes/<mesh>.obj``, ``.glb``,
``.csv`` (per direction) and ``.png`` (sections), as ``python -m solver envelope`` writes them.

A row's envelope columns (m, m^3; docs/tutorials/study.md, "Reach envelopes in a study"): the reach in the set
conditions (``balanced_mean_m``, ``balanced_min_m``, ``balanced_max_m``) and without balance (``kinematic_mean_m``), the
arm's length, the mean and largest reach balance takes off (``mean_difference_m``, ``max_difference_m``,
``worst_sector``, ``front_low_difference_m``), the volumes and the share of the volume lost to balance
(``volume_lost``), with stepping feet the planted reach and what stepping adds (``planted_mean_m``, ``stepping_gain_m``,
``stepping_gain_max_m``, ``volume_planted_m3``), directions not reached at all (``unreached``), the solves, and ``mesh``
(the files' path without suffix, relative to OUT). ``status`` is "converged" when every direction was reached.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ..envelope.job import compute_envelope
from ..envelope.outputs import RESULT_COLUMNS, summary_row, write_envelope
from .envelope_spec import mesh_name

if TYPE_CHECKING:
    from ..body.model import Model
    from .plan import Run

FOLDER = "envelopes"  # in the study's output folder
PAYLOAD = "_envelope"  # a row's (envelope, statistics, plot) on the way to the study's process; never journaled
ENVELOPE_COLUMNS = [c for c in RESULT_COLUMNS if c != "time_s"] + ["mesh"]  # the sweep's time is the row's solve_s


def envelope_row(run: Run, model: Model) -> dict:
    """The envelope columns of ``run`` (an envelope run) for the body ``model``, with the envelope itself under
    PAYLOAD for :func:`keep_files`."""
    values = run.parameters
    envelope, stats = compute_envelope(model, values["hand"], run.envelope.settings(values))
    summary = summary_row(envelope, stats)
    reached = stats["unreached"] == 0
    row = {key: summary[key] for key in ENVELOPE_COLUMNS if key in summary}
    row |= dict(status="converged" if reached else "not converged", converged=reached, solve_s=summary["time_s"],
                mesh=f"{FOLDER}/{mesh_name(run.manikin_name, values)}")  # fmt: skip
    row[PAYLOAD] = (envelope, stats, run.envelope.plot)
    return row


def keep_files(folder: Path, rows: list[dict]) -> None:
    """Write the files of each row that carries its envelope (into ``folder``/envelopes) and take the envelope off
    the row (what is left goes into the journal and the tables)."""
    for row in rows:
        payload = row.pop(PAYLOAD, None)
        if payload is None:
            continue
        envelope, stats, plot = payload
        target = folder / FOLDER
        target.mkdir(parents=True, exist_ok=True)
        write_envelope(envelope, stats, target, plot, Path(row["mesh"]).name)
