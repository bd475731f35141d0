"""Population studies: many manikins x scenarios x parameter values, one row per run.

``python -m solver study STUDY.toml -o OUT/`` (docs/tutorials/study.md). One module, one job: ``spec`` (the
study file), ``keypath`` (where a parameter goes in a scenario), ``plan`` (the runs, their seeds and ids),
``runner`` (one run -> its row), ``envelope_spec`` / ``envelope_runs`` (an ``[envelope]``: its settings, its
runs' rows and files), ``execute`` (local processes or Dask), ``outputs`` (journal, CSV, columns),
``plots`` (PNG), ``study`` (the command: resume, run, write).
"""

from __future__ import annotations

from .spec import Study, load_study
from .study import StudyOutcome, run_study

__all__ = ["Study", "StudyOutcome", "load_study", "run_study"]
