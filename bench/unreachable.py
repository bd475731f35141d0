"""Random two-hand reaches with planted feet, most out of reach: do the unmet ones keep the feet and the balance?

    python -m bench.unreachable [TRIALS] [SEED]

Each trial: male_50, both feet planted (all six axes, supports), a position target per hand drawn uniformly in the
ball of 2 m around (0, 0, 1) m clipped to 0..2.2 m height. Prints how many trials were unmet, how many of those had
a foot more than 1 cm off its target or balance more than 1 N off, the worst foot error and the solve times.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from solver.io.scenario.bodies import load_body
from solver.iteration import solve
from solver.problem.problem import Problem, Target

PLANTED = ("x", "y", "z", "rx", "ry", "rz")


def draw_hand(rng: np.random.Generator) -> np.ndarray:
    """A point within 2 m of (0, 0, 1) m, 0..2.2 m high (rejection sampling)."""
    while True:
        p = rng.uniform([-2.0, -2.0, 0.0], [2.0, 2.0, 2.2])
        if np.linalg.norm(p - [0.0, 0.0, 1.0]) <= 2.0:
            return p


def run(trials: int = 300, seed: int = 0) -> str:
    model = load_body(preset="male_50")
    zero = model.forward(model.zero_pose())
    feet = [Target(f, zero.tcp_frame(model.tcp(f))[1], lock=PLANTED, support=True) for f in ("foot_r", "foot_l")]
    rng = np.random.default_rng(seed)
    unmet = foot_off = balance_off = non_finite = 0
    worst_foot, times = 0.0, []
    for _ in range(trials):
        hands = [Target(h, draw_hand(rng), lock=("x", "y", "z")) for h in ("hand_r", "hand_l")]
        t0 = time.perf_counter()
        result = solve(Problem(model, [*feet, *hands]))
        times.append(time.perf_counter() - t0)
        non_finite += not np.isfinite(result.x).all()
        if result.converged:
            continue
        unmet += 1
        foot = max(result.residuals.get("foot_r.position", 0.0), result.residuals.get("foot_l.position", 0.0))
        worst_foot = max(worst_foot, foot)
        foot_off += foot > 0.01
        balance_off += result.residuals.get("balance.force", 0.0) > 1.0
    return (f"{trials} trials (seed {seed}): {unmet} unmet; of those {foot_off} with a foot > 1 cm off, "
            f"{balance_off} with balance > 1 N off (worst foot {worst_foot * 1e3:.1f} mm); non-finite {non_finite}; "
            f"solve median {np.median(times) * 1e3:.0f} ms, p95 {np.percentile(times, 95) * 1e3:.0f} ms")  # fmt: skip


if __name__ == "__main__":
    args = [int(a) for a in sys.argv[1:3]]
    print(run(*args))
