"""``python -m solver job JOB.toml -o OUT/ [-q]``: a job's ergonomics (:mod:`solver.job`: LiFFT, time at each
RULA/REBA/OWAS level) from its motion and its work (cycle time, cycles per shift, the load), written as OUT/job.json,
OUT/job.csv and the one-file report OUT/job.html."""

from __future__ import annotations

import argparse

from .common import EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The ``job`` subcommand on the command line's subparsers ``sub``."""
    p = sub.add_parser("job", help="ergonomics of a job (LiFFT, time at each score level): JSON + CSV + HTML")
    p.add_argument("job", help="job file (TOML), e.g. presets/jobs/box_lift_job.toml")
    p.add_argument("-o", "--output", default="job_out", help="folder for job.json, job.csv, job.html (default job_out)")
    p.add_argument("-q", "--quiet", action="store_true", help="do not print the verdicts")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Evaluate the job and write its report; exit code 0."""
    from ..job import run_job
    from ..job.run import summary_lines

    report = run_job(args.job, args.output)
    if not args.quiet:
        print("\n".join(summary_lines(report)))
    return EXIT_OK
