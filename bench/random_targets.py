"""The thesis's randomized-target benchmark (§6.1.2, tables 6.1-6.3), run on identical trials per setting.

Hand targets (position and orientation, all six axes) are drawn in the industrial workspace box built from
the manikin's own anthropometry; the hands do not cross; each hand's orientation deviates from its neutral
orientation (fingers forward, palm facing the body's midline) by at most Max Dev. The feet (sole centers)
stay on the floor and may slide and turn. Success is judged only by the constraint function (converged).

With ``peers=True`` the first ``peer_trials`` trials of every level are also solved by the peers of
``peers.py`` (scipy's SLSQP on the same NLP, placo's KinematicsSolver on the URDF export), judged by the same
constraint function, and the report gets a "Peers, same trials" section.
"""

from __future__ import annotations

import datetime
import json
import multiprocessing
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from solver.body.model import Model
from solver.body.reduction import DEFAULT_GROUPS, GROUPS
from solver.body.spatial import exp_so3
from solver.io.scenario.bodies import load_body
from solver.iteration import solve
from solver.options import SolverOptions
from solver.problem.problem import Problem, Target
from solver.threads import single_threaded_blas

from .peer_report import NO_COMFORT, PEERS, level_stats, peer_report
from .peers import PeerResult, placo_available, placo_peer, slsqp_peer
from .scenarios import machine, speed_reference, write_section

LEVELS = (np.pi / 8, np.pi / 4, np.pi / 3, np.pi / 2, 2 * np.pi / 3, np.pi)
LEVEL_NAMES = ("pi/8", "pi/4", "pi/3", "pi/2", "2pi/3", "pi")
CONFIGS = {  # name: (balance, reduction groups); the thesis's reduction also had the shoulder rhythm: the last one
    "physics + reduction": (True, DEFAULT_GROUPS),
    "no physics + reduction": (False, DEFAULT_GROUPS),
    "physics, no reduction": (True, ()),
    "physics + reduction + shoulder rhythm": (True, GROUPS),
}
THESIS = {  # Delfs 2012 tables 6.1-6.3: (successes of 1000, max t s, average t s) per Max Dev level
    "physics + reduction": [
        (919, 1.067, 0.333),
        (885, 0.980, 0.361),
        (889, 1.030, 0.370),
        (832, 0.996, 0.423),
        (802, 0.992, 0.464),
        (744, 0.997, 0.532),
    ],
    "no physics + reduction": [
        (916, 0.716, 0.224),
        (898, 0.715, 0.236),
        (850, 0.719, 0.265),
        (834, 0.820, 0.285),
        (806, 0.733, 0.319),
        (752, 0.723, 0.362),
    ],
    "physics, no reduction": [
        (856, 1.841, 0.834),
        (829, 1.870, 0.887),
        (829, 1.840, 0.893),
        (753, 1.863, 0.988),
        (699, 1.853, 1.063),
        (612, 1.852, 1.213),
    ],
}
THESIS["physics + reduction + shoulder rhythm"] = THESIS["physics + reduction"]  # the thesis reduced the shoulders
PRESET = "male_50"


@dataclass(frozen=True)
class Workspace:
    """The workspace box (world, m) of thesis §6.1.2 for a manikin in its zero pose."""

    lower: np.ndarray
    upper: np.ndarray


def workspace_box(model: Model) -> Workspace:
    """Top at the shoulder, bottom at the knuckles (arms hanging), sides at the elbows with the arms stretched
    sideways, back at the body's vertical line, front at the knuckles with the arms stretched forward."""
    kin = model.forward(model.zero_pose())
    at = {name: kin.tcp_frame(model.tcp(name))[1] for name in ("shoulder_r", "elbow_r", "knuckles_r", "pelvis")}
    upper_arm = np.linalg.norm(at["shoulder_r"] - at["elbow_r"])
    reach = np.linalg.norm(at["shoulder_r"] - at["knuckles_r"])
    side = abs(at["shoulder_r"][0]) + upper_arm
    lower = np.array([-side, at["shoulder_r"][1] - reach, at["knuckles_r"][2]])
    upper = np.array([side, at["pelvis"][1], at["shoulder_r"][2]])
    return Workspace(lower, upper)


def neutral_hand_rotation(model: Model, side: str) -> np.ndarray:
    """The hand TCP's zero-pose orientation turned so the fingers point forward (-y), palm to the midline."""
    kin = model.forward(model.zero_pose())
    return exp_so3([-np.pi / 2, 0.0, 0.0]) @ kin.tcp_frame(model.tcp(f"hand_{side}"))[0]


def draw_targets(model: Model, box: Workspace, max_dev: float, seed: int) -> dict:
    """Right and left hand targets for one trial: positions in the box (right hand not left of the left
    hand), orientations within ``max_dev`` rad of neutral (uniform random axis, uniform angle)."""
    rng = np.random.default_rng(seed)
    a, b = rng.uniform(box.lower, box.upper, size=(2, 3))
    right, left = (a, b) if a[0] <= b[0] else (b, a)
    out = {}
    for side, position in (("r", right), ("l", left)):
        axis = rng.normal(size=3)
        angle = rng.uniform(0.0, max_dev)
        rotation = exp_so3(axis / np.linalg.norm(axis) * angle) @ neutral_hand_rotation(model, side)
        out[side] = (position, rotation)
    return out


def trial_problem(model: Model, targets: dict, balance: bool, groups: tuple[str, ...]) -> Problem:
    zero = model.forward(model.zero_pose())
    feet = [
        Target(f, zero.tcp_frame(model.tcp(f))[1], lock=("z", "rx", "ry"), support=True, friction=0.6)
        for f in ("foot_l", "foot_r")
    ]
    hands = [Target(f"hand_{s}", targets[s][0], targets[s][1]) for s in ("r", "l")]
    # the thesis's trials: no floor, no self-collision (python -m bench.collision_cost measures them)
    return Problem(model, [*feet, *hands], balance=balance, reduction=groups, floor=False, self_collision=False)


_MODEL: Model | None = None


def _init_worker() -> None:
    global _MODEL
    _MODEL = load_body(preset=PRESET)


def run_trial(job: tuple[str, int, int]) -> dict:
    """One solve: (config or peer name, level index, seed) -> outcome, with targets and residuals if it failed.

    ``comfort`` is h at the returned pose (our comfort function), for every setting and peer alike.
    """
    config, level, seed = job
    model = _MODEL if _MODEL is not None else load_body(preset=PRESET)
    targets = draw_targets(model, workspace_box(model), LEVELS[level], seed)
    if config in PEERS:
        problem = trial_problem(model, targets, True, ())
        peer: PeerResult = slsqp_peer(problem) if config == "SLSQP" else placo_peer(problem)
        out = dict(config=config, level=level, seed=seed, converged=bool(peer.converged), time_s=peer.time_s,
                   iterations=peer.iterations, comfort=peer.comfort)  # fmt: skip
        if not peer.converged:
            out.update(unmet=list(peer.unmet), worst_scaled_error=peer.worst, message=peer.message)
    else:
        balance, groups = CONFIGS["physics + reduction" if config == NO_COMFORT else config]
        options = SolverOptions(optimize_comfort=config != NO_COMFORT)
        problem = trial_problem(model, targets, balance, groups)
        t0 = time.perf_counter()
        result = solve(problem, options=options)
        elapsed = time.perf_counter() - t0
        out = dict(config=config, level=level, seed=seed, converged=result.converged, time_s=elapsed,
                   iterations=result.iterations, comfort=result.comfort)  # fmt: skip
        if not result.converged:
            out["unmet"] = result.unmet
            out["residuals"] = result.residuals
    if not out["converged"]:
        out["targets"] = {s: dict(position=p.tolist(), rotation=r.tolist()) for s, (p, r) in targets.items()}
    return out


def _pool(processes: int):
    """Worker processes started fresh ("spawn") with single-threaded BLAS, so one process is one core.

    Forked workers inherit the parent's already loaded BLAS with its thread count (2 here): two workers on two
    cores then run four BLAS threads, which made small dense solves (SLSQP's above all) several times slower.
    """
    with single_threaded_blas():
        return multiprocessing.get_context("spawn").Pool(processes, initializer=_init_worker)


def run_random_benchmark(
    output: Path,
    trials: int = 1000,
    processes: int | None = None,
    seed: int = 2012,
    peers: bool = False,
    peer_trials: int | None = None,
) -> str:
    """Run every (config, level, trial), in parallel across cores; write tables, a plot and the failures.

    With ``peers``, the peers also solve the first ``peer_trials`` (default: all) trials of every level.
    """
    # the settings take turns on each trial, so the VM's speed drifts (up to 2x over minutes) hit them alike
    jobs = [(c, lv, seed + 100_000 * lv + i) for i in range(trials) for lv in range(len(LEVELS)) for c in CONFIGS]
    peer_trials = trials if peer_trials is None else max(0, min(peer_trials, trials))
    peer_names = []
    if peers:
        peer_names = ["SLSQP"] + (["placo"] if placo_available() else [])
        # the slow peer first, so that no core waits on a long SLSQP solve at the end
        peer_jobs = [(p, lv, seed + 100_000 * lv + i) for p in [*peer_names, NO_COMFORT] for lv in range(len(LEVELS))
                     for i in range(peer_trials)]  # fmt: skip
        jobs = peer_jobs[: len(LEVELS) * peer_trials] + jobs + peer_jobs[len(LEVELS) * peer_trials :]
    processes = processes or os.cpu_count() or 1
    reference = [speed_reference()]
    outcomes = []
    with _pool(processes) as pool:
        for k, outcome in enumerate(pool.imap_unordered(run_trial, jobs, chunksize=1), 1):
            outcomes.append(outcome)
            if k % 20 == 0 or k == len(jobs):
                bar = "#" * int(40 * k / len(jobs))
                print(f"\r[{bar:<40}] {k}/{len(jobs)}", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    reference.append(speed_reference())
    output = Path(output)
    text = _report(outcomes, trials, processes, reference)
    if peers:
        text += "\n\n" + peer_report(outcomes, peer_trials, peer_names, LEVEL_NAMES)
    write_section(output, "random-bench", text)
    failures = [o for o in outcomes if not o["converged"]]
    fail_path = output.parent / "random_failures.json"
    # one failure per line: thousands of them stay a few MB and diff line by line
    fail_path.write_text("[\n" + ",\n".join(json.dumps(f) for f in failures) + "\n]\n", encoding="utf-8")
    _plot(outcomes, output.parent / "random_benchmark.png")
    print(f"wrote {output}, {fail_path}, {output.parent / 'random_benchmark.png'}")
    return text


def _report(outcomes: list[dict], trials: int, processes: int, reference: list[float]) -> str:
    lines = [
        "## Randomized targets (thesis §6.1.2)",
        "",
        f"Written by `python -m bench --random --trials {trials}` on {datetime.date.today().isoformat()}; "
        f"{trials} trials per level, the same seeds for every setting, {processes} processes (one solve per core, "
        "single-threaded BLAS); the settings take turns on each trial, so the shared VM's speed drifts hit them alike.",
        f"Machine: {machine()}; speed reference (a fixed NumPy workload, lower is faster; compare runs by it) "
        f"{reference[0]:.1f} ms before, {reference[1]:.1f} ms after the trials.",
        f"Manikin {PRESET}; hand targets with all six axes locked, feet sliding on the floor.",
        'Success = the constraint function met (converged). Times in seconds. "reduction" is what',
        "`reduction = true` does: the spine regions and the fingers grouped. The thesis's reduction also coupled",
        "each shoulder's nine joints by the Hogfors rhythm; that is the last setting (2 variables per shoulder:",
        "plane of elevation -10..90 deg, elevation up to 60 deg, no free humeral rotation), compared with the",
        "thesis's physics + reduction table. The goal (average time at most a tenth of the thesis's) is met",
        "where the column average / (thesis / 10) is at most 1.00. Every setting of ours starts a failed solve once",
        "more from the other side of the joints it left at a limit (`restarts = 1`, the default); its time and",
        "iterations include both attempts.",
        "",
    ]
    for config in CONFIGS:
        lines += [
            f"### {config}",
            "",
            "| Max Dev | success | thesis | max t | thesis max t | average t | thesis average t "
            "| average / (thesis / 10) | median t | p95 t |",
            "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
        ]
        for lv, name in enumerate(LEVEL_NAMES):
            ok, n, t = level_stats(outcomes, config, lv)
            th = THESIS[config][lv]
            lines.append(
                f"| {name} | {ok}/{n} | {th[0]}/1000 | {t.max():.3f} | {th[1]:.3f} | {t.mean():.3f} | {th[2]:.3f} "
                f"| {t.mean() / (th[2] / 10):.2f} | {np.median(t):.3f} | {np.percentile(t, 95):.3f} |"
            )
        lines.append("")
    lines.append("Failures (seed, targets, residuals): `docs/random_failures.json`; plot: `docs/random_benchmark.png`.")
    return "\n".join(lines)


def _plot(outcomes: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4))
    x = np.arange(len(LEVELS))
    for k, config in enumerate(CONFIGS):
        color = f"C{k}"
        rates, means = [], []
        for lv in range(len(LEVELS)):
            ok, n, t = level_stats(outcomes, config, lv)
            rates.append(ok / max(n, 1))
            means.append(t.mean())
        ax1.plot(x, rates, "o-", color=color, label=f"ours: {config}")
        ax2.plot(x, means, "o-", color=color, label=f"ours: {config}")
        if config.endswith("shoulder rhythm"):
            continue  # its thesis table is physics + reduction's, drawn already
        ax1.plot(x, [th[0] / 1000 for th in THESIS[config]], "x--", color=color, alpha=0.5, label=f"thesis: {config}")
        ax2.plot(x, [th[2] for th in THESIS[config]], "x--", color=color, alpha=0.5, label=f"thesis: {config}")
    for ax, title in ((ax1, "success rate"), (ax2, "average solve time (s)")):
        ax.set_xticks(x, LEVEL_NAMES)
        ax.set_xlabel("Max Dev of the hand orientation")
        ax.set_title(title)
        ax.grid(alpha=0.3)
    ax2.set_yscale("log")
    ax1.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
