"""``python -m solver kernels``: which kernels the solver computes with (compiled by Numba, or NumPy) and why;
``--compile`` compiles them now (or loads them from the cache) by solving preset scenarios once (:data:`SCENARIOS`)."""

from __future__ import annotations

import argparse
import time

from .common import EXIT_OK

# the presets --compile solves: box_lift reaches most kernels, deep_squat the step's clamping rounds (where J J^T is
# too ill-conditioned for the fused step; a hand moved in Blender reaches them too), cabinet_reach a box obstacle
SCENARIOS = ("box_lift", "deep_squat", "cabinet_reach")


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The ``kernels`` subcommand on the command line's subparsers ``sub``."""
    p = sub.add_parser("kernels", help="say which solver kernels are in use (Numba or NumPy); --compile warms them")
    p.add_argument(
        "--compile",
        action="store_true",
        help="solve box_lift and two more presets once, compiling the kernels into the cache (or loading them); timed",
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

        for name in SCENARIOS:
            start = time.perf_counter()
            [(_, result)] = solve_motion(load_scenario(PRESETS_DIR / "scenarios" / f"{name}.toml"))
            state = "converged" if result.converged else "not converged"
            took = time.perf_counter() - start
            print(f"{name} solved ({state}) in {took:.2f} s, kernels compiled or loaded included", flush=True)
    return EXIT_OK
