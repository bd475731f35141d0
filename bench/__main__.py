"""``python -m bench [--random [--peers]] [-o docs/BENCHMARKS.md]``: time the preset scenarios (or the randomized-target
benchmark) and write the section of docs/BENCHMARKS.md."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench", description=__doc__.split("\n\n")[0])
    parser.add_argument("-o", "--output", default="docs/BENCHMARKS.md")
    parser.add_argument("--repeats", type=int, default=30, help="solves per preset scenario")
    parser.add_argument("--random", action="store_true", help="the thesis's randomized-target benchmark instead")
    parser.add_argument("--trials", type=int, default=1000, help="random trials per level (with --random)")
    parser.add_argument("--processes", type=int, default=None, help="parallel processes (default: all cores)")
    parser.add_argument("--peers", action="store_true",
                         help="--random plus peers (scipy SLSQP, placo if installed) on the same trials")  # fmt: skip
    parser.add_argument("--peer-trials", type=int, default=None,
                         help="trials per level for the peers (default: --trials; SLSQP is slow)")  # fmt: skip
    args = parser.parse_args(argv)
    if args.random or args.peers:
        from .random_targets import run_random_benchmark

        run_random_benchmark(
            Path(args.output), trials=args.trials, processes=args.processes, peers=args.peers,
            peer_trials=args.peer_trials,
        )  # fmt: skip
    else:
        from . import one_core, run_benchmarks

        one_core("bench")
        run_benchmarks(Path(args.output), repeats=args.repeats)
    return 0


if __name__ == "__main__":
    sys.exit(main())
