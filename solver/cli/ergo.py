"""``python -m solver ergo RESULT.json [-o ERGO.json] [NIOSH, RULA/REBA options] [--no-plots] [-q]``: the ergonomic
evaluation of a result file, written as a report JSON with a CSV and PNG plots beside it (:mod:`solver.ergonomics`)."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..io.output_paths import check_distinct, check_output
from .common import EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The ``ergo`` subcommand on the command line's subparsers ``sub``."""
    p = sub.add_parser("ergo", help="ergonomic evaluation of a result JSON: JSON + CSV + PNG plots")
    p.add_argument("result", help="result file (JSON) written by 'solve'")
    p.add_argument("-o", "--output", help="report file (JSON); default RESULT_ergo.json")
    p.add_argument("--load-mass", type=float, help="kg handled (default: the result's loads on the hands)")
    p.add_argument("--frequency", type=float, default=1.0, help="NIOSH lifts per minute (default 1)")
    p.add_argument(
        "--duration",
        default="short",
        choices=["short", "moderate", "long"],
        help="NIOSH lifting duration: <= 1 h, 1-2 h, 2-8 h (default short)",
    )
    p.add_argument("--coupling", default="fair", choices=["good", "fair", "poor", "unacceptable"])
    p.add_argument(
        "--destination-control",
        action="store_true",
        help="NIOSH: significant control at the destination (use the lower RWL)",
    )
    p.add_argument("--travel", type=float, help="NIOSH vertical travel (m) for a one-frame result")
    p.add_argument("--origin", type=int, help="NIOSH origin frame number (default: first)")
    p.add_argument("--destination", type=int, help="NIOSH destination frame number (default: last)")
    p.add_argument(
        "--activity",
        default="intermittent",
        choices=["intermittent", "static", "repeated"],
        help="RULA/REBA muscle use (default intermittent)",
    )
    p.add_argument("--shock", action="store_true", help="sudden or jerky forces (RULA/REBA)")
    p.add_argument("--manikin", help="preset or body TOML for strengths (default: the scenario's manikin)")
    p.add_argument("--no-plots", action="store_true", help="do not write the PNG plots")
    p.add_argument("-q", "--quiet", action="store_true", help="do not print the summary")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Check every file to write, evaluate the result and write the report; exit code 0."""
    from ..ergonomics import ErgoOptions
    from ..ergonomics import run as write_report
    from ..ergonomics.report import summary_lines

    output = _output(args)
    _check_outputs(args, output)
    options = ErgoOptions(
        load_mass=args.load_mass,
        activity=args.activity,
        shock=args.shock,
        coupling=args.coupling,
        frequency=args.frequency,
        duration=args.duration,
        destination_control=args.destination_control,
        travel=args.travel,
        origin=args.origin,
        destination=args.destination,
        manikin=args.manikin,
    )
    report = write_report(args.result, output, options, plots=not args.no_plots)
    if not args.quiet:
        print("\n".join(summary_lines(report)))
    return EXIT_OK


def _output(args: argparse.Namespace) -> Path:
    """The report file: -o, else RESULT_ergo.json beside the result."""
    if args.output is not None:
        return Path(args.output)
    return Path(args.result).with_name(Path(args.result).stem + "_ergo.json")


def _check_outputs(args: argparse.Namespace, output: Path) -> None:
    """The report, its CSV and its plots: each writable, none of them the result file (one line for the first
    problem)."""
    from ..ergonomics import output_files

    check_output(output if args.output is None else args.output, "-o", suffixes=(".json",))
    files = output_files(output, not args.no_plots)
    derived = [("-o" if i == 0 else "-o (beside it)", p) for i, p in enumerate(files)]
    for flag, path in derived[1:]:
        check_output(path, flag)
    check_distinct(derived, [("", args.result)])
