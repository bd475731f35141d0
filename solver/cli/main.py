"""Command line: ``python -m solver solve SCENARIO.toml [-o RESULT.json]``, ``ergo RESULT.json -o ERGO.json``,
``study STUDY.toml -o OUT/``, ``presets``, ``urdf PRESET -o OUT.urdf``, ``family ... -o DIR``
(:mod:`solver.cli.family`), ``envelope [MANIKIN ...] -o DIR`` (:mod:`solver.cli.envelope`).

Exit codes: 0 every frame converged, 3 some frame did not (the JSON is still written), 2 bad input (one line
on stderr naming the file, the key and what was expected), 130 interrupted (Ctrl-C; the frames solved so far are
kept in the result file, which says where the run stopped).
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import ArgumentParser, ManikinError, UsageError
from ..io.files import STDOUT, write_text
from .envelope import add_envelope_parser
from .family import add_family_parser

EXIT_OK, EXIT_BAD_INPUT, EXIT_NOT_CONVERGED, EXIT_INTERRUPTED = 0, 2, 3, 130
EXIT_BROKEN_PIPE = 141  # 128 + SIGPIPE, what a shell reports for a writer whose reader left

if TYPE_CHECKING:
    from ..io.result.write import ResultWriter


def _solve(args: argparse.Namespace) -> int:
    from ..io.result.write import ResultWriter
    from ..io.scenario.read import load_scenario
    from ..motion.frames import solve_motion
    from ..progress import Progress

    scenario = load_scenario(args.scenario)
    frames = scenario.frames
    compact = None if args.format is None else args.format == "compact"
    writer = ResultWriter(args.output, scenario.path, compact) if args.output else None
    progress = Progress(len(frames), enabled=len(frames) > 1 and not args.quiet)
    failed: list[int] = []
    last = None
    try:
        for done, (frame, result) in enumerate(solve_motion(scenario), 1):
            if writer is not None:
                writer.add(frame, result)
            last = result
            if not result.converged:
                failed.append(frame)
            progress.update(done, len(failed))
    except KeyboardInterrupt:
        progress.clear()
        return _interrupted(frames, writer)
    except BaseException as exc:
        progress.clear()
        if writer is not None:  # keep what was solved; the error itself is reported by main
            writer.close(interrupted_at=frames[writer.count] if writer.count < len(frames) else None,
                         reason=" ".join(str(exc).split()) or type(exc).__name__)  # fmt: skip
        raise
    progress.clear()
    out = writer.close() if writer is not None else None
    if not args.quiet:
        print(last.summary())
        if len(frames) > 1:
            took = progress.elapsed()
            shown = f"{failed[:20]}".rstrip("]") + (", ...]" if len(failed) > 20 else "]")
            missed = f"; not converged: {len(failed)} {shown}" if failed else ""
            print(f"{len(frames)} frames in {took:.1f} s ({len(frames) / max(took, 1e-9):.0f} frames/s), "
                  f"{len(frames) - len(failed)} converged{missed}")  # fmt: skip
        if out is not None:
            print(f"wrote {out}")
    return EXIT_NOT_CONVERGED if failed else EXIT_OK


def _interrupted(frames: list[int], writer: ResultWriter | None) -> int:
    """Ctrl-C in the frame loop: keep the solved frames (the file says where it stopped) and say so in one line."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the solved frames are being kept: a second Ctrl-C waits
    solved = 0 if writer is None else writer.count
    at = frames[min(solved, len(frames) - 1)]
    if writer is None:
        print(f"interrupted at frame {at}; nothing kept (no -o RESULT given)", file=sys.stderr)
        return EXIT_INTERRUPTED
    kept = writer.close(interrupted_at=at, reason="interrupted (Ctrl-C)")
    where = f"in {kept}" if kept is not None else f"({writer.path} not written)"
    print(f"interrupted at frame {at}; kept {solved} solved frames {where}", file=sys.stderr)
    return EXIT_INTERRUPTED


def _ergo(args: argparse.Namespace) -> int:
    from ..ergonomics import ErgoOptions, run
    from ..ergonomics.report import summary_lines

    options = ErgoOptions(
        load_mass=args.load_mass, activity=args.activity, shock=args.shock, coupling=args.coupling,
        frequency=args.frequency, duration=args.duration, destination_control=args.destination_control,
        travel=args.travel, origin=args.origin, destination=args.destination, manikin=args.manikin,
    )  # fmt: skip
    report = run(args.result, _ergo_output(args), options, plots=not args.no_plots)
    if not args.quiet:
        print("\n".join(summary_lines(report)))
    return EXIT_OK


def _study(args: argparse.Namespace) -> int:
    from ..study import run_study

    if args.scenario_of is not None:
        from ..study.export import row_scenario

        write_text(args.output or STDOUT, row_scenario(args.study, args.scenario_of))
        return EXIT_OK
    if args.output is None:
        raise UsageError("study needs -o OUT (the output folder), or --scenario-of RUN_ID")

    if args.workers is not None and args.workers < 1:
        raise UsageError(f"--workers: expected a whole number >= 1, got {args.workers}")
    if args.chunk is not None and args.chunk < 1:
        raise UsageError(f"--chunk: expected a whole number >= 1, got {args.chunk}")
    outcome = run_study(args.study, args.output, args.workers, args.dask, args.chunk, args.retry_failed, args.quiet)
    if outcome.interrupted:
        print(f"interrupted; kept {outcome.converged + outcome.not_converged + outcome.failed} of {outcome.total} "
              f"runs in {args.output} (run the same command again to go on)", file=sys.stderr)  # fmt: skip
        return EXIT_INTERRUPTED
    if not args.quiet:
        print(outcome.line())
    return EXIT_OK if outcome.converged == outcome.total else EXIT_NOT_CONVERGED


def _urdf(args: argparse.Namespace) -> int:
    from ..io.scenario.bodies import load_body
    from ..io.urdf import model_to_urdf, write_urdf

    if (args.preset is None) == (args.file is None):
        raise UsageError("urdf needs a manikin preset name or --file BODY.toml (one of them)")
    model = load_body(preset=args.preset, file=args.file)
    if args.output and args.output != STDOUT:
        print(f"wrote {write_urdf(model, args.output)} ({model.n} joints, {len(model.tcps)} TCP frames)")
    else:
        write_text(STDOUT, model_to_urdf(model))
    return EXIT_OK


def _ergo_output(args: argparse.Namespace) -> Path:
    """The report file: -o, else RESULT_ergo.json beside the result."""
    if args.output is not None:
        return Path(args.output)
    return Path(args.result).with_name(Path(args.result).stem + "_ergo.json")


def check_paths(args: argparse.Namespace) -> None:
    """Every file the command will write, checked before any work: one UsageError line for the first problem."""
    from ..io.output_paths import check_distinct, check_output

    if args.command in ("solve", "urdf") and args.output is not None:
        check_output(args.output, "-o", stdout=True)
        check_distinct([("-o", args.output)], [("", args.scenario if args.command == "solve" else args.file)])
    elif args.command == "ergo":
        from ..ergonomics import output_files

        output = _ergo_output(args)
        check_output(output if args.output is None else args.output, "-o", suffixes=(".json",))
        files = output_files(output, not args.no_plots)
        derived = [("-o" if i == 0 else "-o (beside it)", p) for i, p in enumerate(files)]
        for flag, path in derived[1:]:
            check_output(path, flag)
        check_distinct(derived, [("", args.result)])


def keep_stdout_for_the_file(args: argparse.Namespace) -> None:
    """``-o -``: standard output carries the result JSON (or URDF), so the summary is left out (as with -q)."""
    if getattr(args, "output", None) == STDOUT and args.command in ("solve", "urdf"):
        args.quiet = True


def _presets(args: argparse.Namespace) -> int:
    from ..io.scenario.bodies import PRESETS_DIR, list_presets

    print("manikins: " + ", ".join(list_presets()))
    scenarios = sorted((PRESETS_DIR / "scenarios").glob("*.toml"))
    print("scenarios: " + ", ".join(_from_here(p) for p in scenarios))
    families = sorted(p.parent for p in (PRESETS_DIR / "families").glob("*/family.toml"))
    print("families: " + ", ".join(_from_here(p) for p in families))
    return EXIT_OK


def _from_here(path: Path) -> str:
    """``path`` as a user types it here: relative to the working directory inside it (presets/... at the checkout's
    root), else absolute (the command runs from anywhere)."""
    try:
        return path.relative_to(Path.cwd().resolve()).as_posix()
    except ValueError:
        return str(path)


def build_parser() -> argparse.ArgumentParser:
    """The command line's parser; a bad argument raises one UsageError line instead of printing the usage."""
    parser = ArgumentParser(prog="python -m solver", description="Manikin pose prediction solver")
    sub = parser.add_subparsers(dest="command", required=True)
    p_solve = sub.add_parser("solve", help="solve a scenario TOML and write the result JSON")
    p_solve.add_argument("scenario", help="scenario file (TOML)")
    p_solve.add_argument("-o", "--output", help="result file: JSON, or compact JSON Lines for a .jsonl name")
    p_solve.add_argument("--format", choices=["json", "compact"],
                         help="result format (default: compact for a .jsonl file, else json); compact: the model "
                         "once, then per frame joint values, contacts and loads (for long motions)")  # fmt: skip
    p_solve.add_argument("-q", "--quiet", action="store_true", help="print no summary and no progress")
    p_solve.set_defaults(run=_solve)
    p_ergo = sub.add_parser("ergo", help="ergonomic evaluation of a result JSON: JSON + CSV + PNG plots")
    p_ergo.add_argument("result", help="result file (JSON) written by 'solve'")
    p_ergo.add_argument("-o", "--output", help="report file (JSON); default RESULT_ergo.json")
    p_ergo.add_argument("--load-mass", type=float, help="kg handled (default: the result's loads on the hands)")
    p_ergo.add_argument("--frequency", type=float, default=1.0, help="NIOSH lifts per minute (default 1)")
    p_ergo.add_argument("--duration", default="short", choices=["short", "moderate", "long"],
                        help="NIOSH lifting duration: <= 1 h, 1-2 h, 2-8 h (default short)")  # fmt: skip
    p_ergo.add_argument("--coupling", default="fair", choices=["good", "fair", "poor", "unacceptable"])
    p_ergo.add_argument("--destination-control", action="store_true",
                        help="NIOSH: significant control at the destination (use the lower RWL)")  # fmt: skip
    p_ergo.add_argument("--travel", type=float, help="NIOSH vertical travel (m) for a one-frame result")
    p_ergo.add_argument("--origin", type=int, help="NIOSH origin frame number (default: first)")
    p_ergo.add_argument("--destination", type=int, help="NIOSH destination frame number (default: last)")
    p_ergo.add_argument("--activity", default="intermittent", choices=["intermittent", "static", "repeated"],
                        help="RULA/REBA muscle use (default intermittent)")  # fmt: skip
    p_ergo.add_argument("--shock", action="store_true", help="sudden or jerky forces (RULA/REBA)")
    p_ergo.add_argument("--manikin", help="preset or body TOML for strengths (default: the scenario's manikin)")
    p_ergo.add_argument("--no-plots", action="store_true", help="do not write the PNG plots")
    p_ergo.add_argument("-q", "--quiet", action="store_true", help="do not print the summary")
    p_ergo.set_defaults(run=_ergo)
    p_study = sub.add_parser("study", help="run a study (manikins x scenarios x parameters): rows, columns, plots")
    p_study.add_argument("study", help="study file (TOML)")
    p_study.add_argument("-o", "--output", help="output folder (a rerun skips the runs it holds); with --scenario-of: "
                         "the scenario file (default: standard output)")  # fmt: skip
    p_study.add_argument("--scenario-of", metavar="RUN_ID", help="write the scenario of one row (its run_id or "
                         "a unique start of it) instead of running the study (`solve` on it: its pose)")  # fmt: skip
    p_study.add_argument("--workers", type=int, help="local worker processes (default: all cores)")
    p_study.add_argument("--dask", metavar="SCHEDULER", help="run on Dask: a scheduler address, or 'local' for a "
                         "LocalCluster of --workers processes (needs requirements-dask.txt)")  # fmt: skip
    p_study.add_argument("--chunk", type=int, help="runs per task (default: by the run count and the workers)")
    p_study.add_argument("--retry-failed", action="store_true", help="run again the failed runs the folder holds")
    p_study.add_argument("-q", "--quiet", action="store_true", help="print no summary and no progress")
    p_study.set_defaults(run=_study)
    p_urdf = sub.add_parser("urdf", help="export a manikin to URDF (joints, limits, masses, TCP frames)")
    p_urdf.add_argument("preset", nargs="?", help="manikin preset (see 'presets')")
    p_urdf.add_argument("--file", help="body TOML instead of a preset")
    p_urdf.add_argument("-o", "--output", help="URDF file to write (default: standard output)")
    p_urdf.set_defaults(run=_urdf)
    p_presets = sub.add_parser("presets", help="list the manikin and scenario presets")
    p_presets.set_defaults(run=_presets)
    add_family_parser(sub)
    add_envelope_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run one command; its exit code (bad input: one line on stderr starting ``error:``, exit 2)."""
    try:
        args = build_parser().parse_args(argv)
        check_paths(args)
        keep_stdout_for_the_file(args)
        return args.run(args)
    except ManikinError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except BrokenPipeError:  # the reader of our output stopped (``| head``): quiet, as other tools are
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # so Python's own flush at exit is quiet too
        return EXIT_BROKEN_PIPE
    except OSError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED


if __name__ == "__main__":
    sys.exit(main())
