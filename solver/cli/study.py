"""``python -m solver study STUDY.toml -o OUT/ [--workers N | --dask SCHEDULER] [--chunk N] [--retry-failed] [-q]``:
run a study (manikins x scenarios x parameters) into a folder, whose rows a rerun skips; or ``--scenario-of
RUN_ID [-o FILE]``: write the scenario of one of its rows (:mod:`solver.study`)."""

from __future__ import annotations

import argparse
import sys

from ..errors import UsageError
from ..io.files import STDOUT, write_text
from ..io.interrupts import stopped_by
from .common import EXIT_INTERRUPTED, EXIT_NOT_CONVERGED, EXIT_OK, check_count


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The ``study`` subcommand on the command line's subparsers ``sub``."""
    p = sub.add_parser("study", help="run a study (manikins x scenarios x parameters): rows, columns, plots")
    p.add_argument("study", help="study file (TOML)")
    p.add_argument(
        "-o",
        "--output",
        help="output folder (a rerun skips the runs it holds); with --scenario-of: the scenario file (default: "
        "standard output)",
    )
    p.add_argument(
        "--scenario-of",
        metavar="RUN_ID",
        help="write the scenario of one row (its run_id or a unique start of it) instead of running the study "
        "(`solve` on it: its pose)",
    )
    p.add_argument("--workers", type=int, help="local worker processes (default: all cores)")
    p.add_argument(
        "--dask",
        metavar="SCHEDULER",
        help="run on Dask: a scheduler address, or 'local' for a LocalCluster of --workers processes (needs "
        "requirements-dask.txt)",
    )
    p.add_argument("--chunk", type=int, help="runs per task (default: by the run count and the workers)")
    p.add_argument("--retry-failed", action="store_true", help="run again the failed runs the folder holds")
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary and no progress")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run the study (0 when every run converged, else 3; 130 on Ctrl-C or SIGTERM), or write one row's scenario (0)."""
    from ..study import run_study

    if args.scenario_of is not None:
        from ..study.export import row_scenario

        write_text(args.output or STDOUT, row_scenario(args.study, args.scenario_of))
        return EXIT_OK
    if args.output is None:
        raise UsageError("study needs -o OUT (the output folder), or --scenario-of RUN_ID")
    check_count(args.workers, "--workers")
    check_count(args.chunk, "--chunk")
    outcome = run_study(args.study, args.output, args.workers, args.dask, args.chunk, args.retry_failed, args.quiet)
    if outcome.interrupted:
        kept = outcome.converged + outcome.not_converged + outcome.failed
        again = "(run the same command again to go on)"
        why = "" if stopped_by() == "Ctrl-C" else f" ({stopped_by()})"
        print(f"interrupted{why}; kept {kept} of {outcome.total} runs in {args.output} {again}", file=sys.stderr)
        return EXIT_INTERRUPTED
    if not args.quiet:
        print(outcome.line())
    return EXIT_OK if outcome.converged == outcome.total else EXIT_NOT_CONVERGED
