"""``python -m solver study STUDY.toml -o OUT/``: plan a study, run what is not in OUT yet, write rows and plots."""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import UsageError
from ..progress import Progress
from .envelope_runs import keep_files
from .execute import chunk_size, run_dask, run_local
from .outputs import Journal, read_journal, write_tables
from .plan import Run, parameter_names, plan
from .plots import write_plots
from .runner import columns
from .spec import Study, load_study, member_columns


@dataclass
class StudyOutcome:
    """What a study did: counts of its rows, the time and workers of this call, the files written."""

    name: str
    total: int  # rows the study has
    new: int = 0  # rows run by this call
    kept: int = 0  # rows found in the output folder (not run again)
    converged: int = 0
    not_converged: int = 0
    failed: int = 0
    seconds: float = 0.0
    workers: int = 0
    dask: str | None = None  # the scheduler's address, "local" (a LocalCluster), or None: local processes
    interrupted: bool = False
    written: list[Path] = field(default_factory=list)

    def line(self) -> str:
        """The summary line ``study`` prints."""
        rate = f", {self.new / self.seconds:.1f} runs/s" if self.seconds > 0 else ""
        head = f"study {self.name}: {self.converged + self.not_converged + self.failed} of {self.total} runs"
        plural = "" if self.workers == 1 else "s"
        if self.dask is None:
            where = f"{self.workers} local process{'es' if plural else ''}{rate}"
        else:
            where = (
                f"{self.workers} Dask worker{plural} ({'LocalCluster' if self.dask == 'local' else self.dask}){rate}"
            )
        done = f" ({self.new} now in {self.seconds:.1f} s on {where}, {self.kept} from before)" if self.new else ""
        done = done or f" (all {self.kept} from before)"
        counts = f": {self.converged} converged, {self.not_converged} not converged, {self.failed} failed"
        return head + done + counts + "; wrote " + ", ".join(map(str, self.written))


def cores() -> int:
    """The cores this process may use (its CPU affinity where the system tells it, else the machine's count)."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0)) or 1
    return os.cpu_count() or 1


def output_folder(path: str | Path) -> Path:
    """``-o``: a folder (made if missing); a file in the way is one UsageError line."""
    folder = Path(path)
    if folder.exists() and not folder.is_dir():
        raise UsageError(f"-o {folder}: is a file, expected a folder for the study's outputs")
    return folder


def run_study(
    study_file: str | Path,
    output: str | Path,
    workers: int | None = None,
    dask: str | None = None,
    chunk: int | None = None,
    retry_failed: bool = False,
    quiet: bool = False,
) -> StudyOutcome:
    """Run every run of the study that ``output`` does not hold yet (``retry_failed``: failed ones too) on
    ``workers`` local processes (default all cores) or the Dask scheduler ``dask`` ("local": a LocalCluster), in
    chunks of ``chunk`` runs (default: by the run count); then write the rows and plots of all runs done."""
    study = load_study(study_file)
    folder = output_folder(output)
    runs = plan(study)
    before = read_journal(folder)
    rows = {r.run_id: before[r.run_id] for r in runs if r.run_id in before}
    if retry_failed:
        rows = {k: row for k, row in rows.items() if row.get("status") != "failed"}
    todo = [r for r in runs if r.run_id not in rows]
    workers = max(1, workers or cores())
    outcome = StudyOutcome(study.name, len(runs), kept=len(rows), workers=min(workers, max(len(todo), 1)))
    outcome.dask = dask
    t0 = time.perf_counter()
    try:
        _run(study, todo, rows, folder, outcome, dask, chunk, quiet)
    except KeyboardInterrupt:
        outcome.interrupted = True
    outcome.seconds = time.perf_counter() - t0
    _finish(study, runs, rows, folder, outcome)
    return outcome


def _run(study: Study, todo: list[Run], rows: dict, folder: Path, outcome: StudyOutcome, dask: str | None,
         chunk: int | None, quiet: bool) -> None:  # fmt: skip
    """Run ``todo``, each row into ``rows`` and the journal as its chunk finishes, with progress on stderr."""
    progress = Progress(len(todo), enabled=not quiet and bool(todo), what="runs")
    journal = Journal(folder)
    missed = 0

    def on_rows(new: list[dict], keep: bool) -> None:
        nonlocal missed
        keep_files(folder, new)  # an envelope's files before its row: a row in the journal has its files
        if keep:
            journal.add(new)
        for row in new:
            rows[row["run_id"]] = row
            missed += row.get("status") != "converged"
        outcome.new += len(new)
        progress.update(outcome.new, missed)

    try:
        if not todo:
            return
        if dask:
            outcome.workers = run_dask(todo, dask, outcome.workers, chunk, on_rows)
        else:
            run_local(todo, outcome.workers, chunk or chunk_size(len(todo), outcome.workers), on_rows)
    finally:
        journal.close()
        progress.clear()


def _finish(study: Study, runs: list[Run], rows: dict, folder: Path, outcome: StudyOutcome) -> None:
    """Count the rows and write the tables and plots of every run done, in the study's order."""
    ordered = [rows[r.run_id] for r in runs if r.run_id in rows]
    for row in ordered:
        status = row.get("status")
        outcome.converged += status == "converged"
        outcome.not_converged += status == "not converged"
        outcome.failed += status == "failed"
    names = parameter_names(study)
    scenarios, envelope = bool(study.scenarios), study.envelope is not None
    table = columns(names, study.record, member_columns(study), scenarios, envelope)
    outcome.written = write_tables(folder, table, ordered)
    panels = [(s.name, p.name) for s in study.scenarios for p in s.parameters]
    panels += [(s.name, None) for s in study.scenarios if not s.parameters]
    manikins = list(dict.fromkeys(r.manikin_name for r in runs))
    record = study.record if scenarios else ()
    outcome.written += write_plots(folder, ordered, panels, manikins, record, study.envelope)
