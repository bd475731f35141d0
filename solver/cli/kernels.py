"""``python -m solver kernels``: which kernels the solver computes with (compiled by Numba, or NumPy) and why;
``--compile`` compiles them now (or loads them from the cache) by solving a preset scenario once."""

from __future__ import annotations

import argparse
import time

from .common import EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The ``kernels`` subcommand on the command line's subparsers ``sub``."""
    p = sub.add_parser("kernels", help="say which solver kernels are in use (Numba or NumPy); --compile warms them")
    p.add_argument(
        "--compile",
        action="store_true",
        help="solve the box_lift preset once, compiling the kernels into the cache (or loading them), and time it",
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Print the kernels' status line (and with --compile the first solve's time); exit code 0."""
    from .. import kernels

    print(f"kernels: {kernels.status()}")
    if args.compile:
        from ..io.scenario.bodies import PRESETS_DIR
        from ..io.scenario.read import load_scenario
        from ..motion.frames import solve_motion

        start = time.perf_counter()
        [(_, result)] = solve_motion(load_scenario(PRESETS_DIR / "scenarios" / "box_lift.toml"))
        state = "converged" if result.converged else "not converged"
        print(f"box_lift solved ({state}) in {time.perf_counter() - start:.2f} s, kernels compiled or loaded included")
    return EXIT_OK
