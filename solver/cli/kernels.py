"""``python -m solver kernels``: which kernels the solver computes with (compiled by Numba, or NumPy) and why;
``--compile`` compiles them now (or loads them from the cache) by solving preset scenarios once (:data:`SCENARIOS`)."""

from __future__ import annotations

import argparse
import time
from dataclasses import replace

from .common import EXIT_OK

# the presets --compile solves (name, frames solved: all of a single pose): box_lift reaches most kernels, deep_squat
# the step's clamping rounds (where J J^T is too ill-conditioned for the fused step; a hand moved in Blender reaches
# them too), cabinet_reach a box obstacle, box_lift_motion's first frames the check of the way between two frames
SCENARIOS = (("box_lift", None), ("deep_squat", None), ("cabinet_reach", None), ("box_lift_motion", 12))


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The ``kernels`` subcommand on the command line's subparsers ``sub``."""
    p = sub.add_parser("kernels", help="say which solver kernels are in use (Numba or NumPy); --compile warms them")
    p.add_argument(
        "--compile",
        action="store_true",
        help="solve box_lift, two more presets and a motion's first frames once, compiling the kernels into the cache"
        " (or loading them); timed",
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

        for name, frames in SCENARIOS:
            start = time.perf_counter()
            scenario = load_scenario(PRESETS_DIR / "scenarios" / f"{name}.toml")
            if frames is not None:
                scenario = replace(scenario, frames=scenario.frames[:frames])
            results = [result for _, result in solve_motion(scenario)]
            state = "converged" if all(r.converged for r in results) else "not converged"
            took = time.perf_counter() - start
            label = name if frames is None else f"{name} {len(results)} frames"
            print(f"{label} solved ({state}) in {took:.2f} s, kernels compiled or loaded included", flush=True)
    return EXIT_OK
