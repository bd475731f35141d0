"""``python -m solver solve SCENARIO.toml [-o RESULT.json|RESULT.jsonl|-] [--format json|compact] [--feet planted|step]
[-q]``: solve every frame of a scenario (the feet planted unless ``--feet step`` or [stance] feet = "step" lets them
step, :mod:`solver.stance`), write the result file as the frames are solved, and print a summary (each step taken).
Exit 3 when a frame did not converge; on Ctrl-C (or SIGTERM) the frames solved so far are kept and the file says
where the run stopped."""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from ..io.files import STDOUT
from ..io.interrupts import ignore_stops, stopped_by
from .common import EXIT_INTERRUPTED, EXIT_NOT_CONVERGED, EXIT_OK, StartupWithoutGC, check_file_output

if TYPE_CHECKING:
    from ..io.result.write import ResultWriter


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The ``solve`` subcommand on the command line's subparsers ``sub``."""
    p = sub.add_parser("solve", help="solve a scenario TOML and write the result JSON")
    p.add_argument("scenario", help="scenario file (TOML)")
    p.add_argument("-o", "--output", help="result file: JSON, or compact JSON Lines for a .jsonl name")
    p.add_argument(
        "--format",
        choices=["json", "compact"],
        help="result format (default: compact for a .jsonl file, else json); compact: the model once, then per frame "
        "joint values, contacts and loads (for long motions)",
    )
    p.add_argument(
        "--feet",
        choices=["planted", "step"],
        help="planted (the default, or the scenario's [stance] feet): can the worker do this from here; step: the feet "
        "may step (each within a step of where it stood, in balance, clear of obstacles), each step reported",
    )
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary and no progress")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Solve the frames in order, each written as it is solved; 0 when all converged, else 3."""
    check_file_output(args.output, args.scenario)
    with StartupWithoutGC() as startup:  # over once the first frame is solved (every kernel it needs loaded)
        return _solve(args, startup)


def _solve(args: argparse.Namespace, startup: StartupWithoutGC) -> int:
    """:func:`run`'s work, within the command's start-up."""
    from ..io.result.write import ResultWriter
    from ..io.scenario.read import load_scenario
    from ..motion.frames import solve_motion
    from ..progress import Progress

    quiet = args.quiet or args.output == STDOUT  # standard output carries the result: no summary there
    scenario = load_scenario(args.scenario, feet=args.feet)
    frames = scenario.frames
    compact = None if args.format is None else args.format == "compact"
    writer = ResultWriter(args.output, scenario.path, compact) if args.output else None
    progress = Progress(len(frames), enabled=len(frames) > 1 and not quiet)
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
            startup.over()
    except KeyboardInterrupt:
        progress.clear()
        return _interrupted(frames, writer)
    except BaseException as exc:
        progress.clear()
        if writer is not None:  # keep what was solved; the error itself is reported by main
            writer.close(
                interrupted_at=frames[writer.count] if writer.count < len(frames) else None,
                reason=" ".join(str(exc).split()) or type(exc).__name__,
            )
        raise
    progress.clear()
    out = writer.close() if writer is not None else None
    if not quiet:
        print(last.summary())
        if len(frames) > 1:
            _print_motion(frames, failed, progress.elapsed())
        if out is not None:
            print(f"wrote {out}")
    return EXIT_NOT_CONVERGED if failed else EXIT_OK


def _print_motion(frames: list[int], failed: list[int], took: float) -> None:
    """A motion's line: its frames, the time they took (s), the rate, and the frames that did not converge."""
    shown = f"{failed[:20]}".rstrip("]") + (", ...]" if len(failed) > 20 else "]")
    missed = f"; not converged: {len(failed)} {shown}" if failed else ""
    rate = len(frames) / max(took, 1e-9)
    print(f"{len(frames)} frames in {took:.1f} s ({rate:.0f} frames/s), {len(frames) - len(failed)} converged{missed}")


def _interrupted(frames: list[int], writer: ResultWriter | None) -> int:
    """Ctrl-C or SIGTERM in the frame loop: keep the solved frames (the file says where it stopped) and say so in
    one line."""
    ignore_stops()  # the solved frames are being kept: a second Ctrl-C or SIGTERM waits
    solved = 0 if writer is None else writer.count
    at = frames[min(solved, len(frames) - 1)]
    if writer is None:
        print(f"interrupted at frame {at}; nothing kept (no -o RESULT given)", file=sys.stderr)
        return EXIT_INTERRUPTED
    kept = writer.close(interrupted_at=at, reason=f"interrupted ({stopped_by()})")
    where = f"in {kept}" if kept is not None else f"({writer.path} not written)"
    print(f"interrupted at frame {at}; kept {solved} solved frames {where}", file=sys.stderr)
    return EXIT_INTERRUPTED
