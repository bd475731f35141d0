"""``python -m solver operate SCENARIO.toml -o OUT/ [-q]``: a scenario's ``[[operations]]`` over its ``[[objects]]``
planned (timing, ways, steps) and every frame solved; writes ``OUT/result.json`` (the same result file as a
motion: ``manikin ergo`` and Blender's bake read it) and ``OUT/summary.txt``. Exit 3 when a frame did not converge,
2 for a bad operation (one line naming it)."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from .common import EXIT_NOT_CONVERGED, EXIT_OK, check_folder_name


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The ``operate`` subcommand on the command line's subparsers ``sub``."""
    p = sub.add_parser("operate", help="plan and solve a scenario's [[operations]] into a motion")
    p.add_argument("scenario", help="scenario file (TOML) with [[objects]] and [[operations]]")
    p.add_argument("-o", "--output", required=True, help="folder for result.json and summary.txt")
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Plan, solve every frame (written as solved), write the summary; 0 when all converged, else 3."""
    check_folder_name(args.output)
    from ..io.result.write import ResultWriter
    from ..operations.generate import load_operations, solve_operations, summary
    from ..progress import Progress

    job = load_operations(args.scenario)
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    converged: dict[int, bool] = {}
    progress = Progress(len(job.frames), enabled=not args.quiet)  # on standard error (Blender's panel reads it)
    with ResultWriter(out / "result.json", job.scenario.path) as writer:
        for frame, result in solve_operations(job):
            writer.add(frame, result)
            converged[frame] = result.converged
            progress.update(len(converged), len(converged) - sum(converged.values()))
    progress.clear()
    lines = summary(job, converged, time.perf_counter() - started)
    (out / "summary.txt").write_text("\n".join(lines) + "\n", encoding="utf-8")
    if not args.quiet:
        print("\n".join(lines))
        print(f"wrote {out / 'result.json'}, {out / 'summary.txt'}")
    return EXIT_OK if all(converged.values()) else EXIT_NOT_CONVERGED
