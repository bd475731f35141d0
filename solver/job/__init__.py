"""Ergonomics of a job, not a frame: a job file (:mod:`.spec`) names the motion of one work cycle and the work around
it (cycle time, cycles per shift, shift length, the load and the hands holding it); each method (one module each,
listed in :mod:`.registry`: ``lifft``, ``sequence``, ``shoulder_tool``) rates the job from the motion's frames and
their per-frame ergonomics (:mod:`solver.ergonomics`); :mod:`.write` writes job.json, job.csv and a one-file HTML
report (:mod:`.html`). A new method is one module and one line in :mod:`.registry`."""

from __future__ import annotations

from .run import evaluate_job, run_job
from .spec import Job, read_job

__all__ = ["Job", "evaluate_job", "read_job", "run_job"]
