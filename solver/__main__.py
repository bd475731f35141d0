"""Command line: ``python -m solver solve SCENARIO.toml [-o RESULT.json]``, ``bench``, ``presets``.

Exit codes: 0 every frame converged, 3 some frame did not (the JSON is still written), 2 bad input (one line
on stderr naming the file, the key and what was expected).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from .errors import ManikinError

EXIT_OK, EXIT_BAD_INPUT, EXIT_NOT_CONVERGED = 0, 2, 3


def _solve(args: argparse.Namespace) -> int:
    from .motion import solve_frames
    from .scenario import load_scenario, result_to_dict

    scenario = load_scenario(args.scenario)
    frames, failed, last = [], [], None
    solved = solve_frames(scenario.problem_at, scenario.frames, scenario.start, scenario.options, scenario.limits)
    for frame, result in solved:
        frames.append(result_to_dict(result, frame))
        last = result
        if not result.converged:
            failed.append(frame)
        if len(scenario.frames) > 1 and not args.quiet:
            status = "ok" if result.converged else "NOT converged: " + ", ".join(result.unmet)
            print(f"frame {frame}: {result.iterations} iterations, {result.time_s * 1e3:.1f} ms, {status}")
    if not args.quiet:
        print(last.summary())
        if len(frames) > 1:
            missed = f"; not converged: {failed}" if failed else ""
            print(f"{len(frames)} frames, {len(frames) - len(failed)} converged{missed}")
    if args.output:
        out = Path(args.output)
        out.parent.mkdir(parents=True, exist_ok=True)
        payload = {"scenario": str(scenario.path), "frames": frames}
        tmp = out.with_name(out.name + ".tmp")
        tmp.write_text(json.dumps(payload, indent=1), encoding="utf-8")
        tmp.replace(out)
        if not args.quiet:
            print(f"wrote {out}")
    return EXIT_NOT_CONVERGED if failed else EXIT_OK


def _bench(args: argparse.Namespace) -> int:
    from .bench import run_benchmarks

    run_benchmarks(Path(args.output), repeats=args.repeats)
    return EXIT_OK


def _presets(args: argparse.Namespace) -> int:
    from .bodies import PRESETS_DIR, list_presets

    print("manikins: " + ", ".join(list_presets()))
    scenarios = sorted(p.name for p in (PRESETS_DIR / "scenarios").glob("*.toml"))
    print("scenarios: " + ", ".join(f"presets/scenarios/{s}" for s in scenarios))
    return EXIT_OK


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m solver", description="Manikin pose prediction solver")
    sub = parser.add_subparsers(dest="command", required=True)
    p_solve = sub.add_parser("solve", help="solve a scenario TOML and write the result JSON")
    p_solve.add_argument("scenario", help="scenario file (TOML)")
    p_solve.add_argument("-o", "--output", help="result file (JSON)")
    p_solve.add_argument("-q", "--quiet", action="store_true", help="do not print the summary")
    p_solve.set_defaults(run=_solve)
    p_bench = sub.add_parser("bench", help="time the preset scenarios and write docs/BENCHMARKS.md")
    p_bench.add_argument("-o", "--output", default="docs/BENCHMARKS.md")
    p_bench.add_argument("--repeats", type=int, default=30)
    p_bench.set_defaults(run=_bench)
    p_presets = sub.add_parser("presets", help="list the manikin and scenario presets")
    p_presets.set_defaults(run=_presets)
    args = parser.parse_args(argv)
    try:
        return args.run(args)
    except ManikinError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except OSError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT


if __name__ == "__main__":
    sys.exit(main())
