"""The random benchmark's "Peers, same trials" section: success, time and comfort, ours beside each peer."""

from __future__ import annotations

import numpy as np

PEERS = {  # name: what it solves (all on the physics, no reduction problem: 160 joints + 32 force weights)
    "SLSQP": "scipy.optimize.minimize(method='SLSQP'): maximise comfort h subject to our scaled constraint rows = 0 "
    "and our bounds (joint ranges, forces >= 0), our exact gradients and Jacobians, from our start",
    "placo": "placo KinematicsSolver on the URDF export: feet soft tasks (z, roll, pitch; weight 100), CoM inside "
    "the soles' convex hull (hard), hands soft frame tasks; no comfort, no forces (found afterwards by NNLS)",
}
NO_COMFORT = "physics + reduction, comfort off"  # ours on the peers' trials, meeting the constraints only (like placo)

OURS_FOR_PEERS = ("physics + reduction", "physics, no reduction", NO_COMFORT)


def level_stats(outcomes: list[dict], config: str, level: int) -> tuple[int, int, np.ndarray]:
    """(successes, trials, times s) of one setting at one level."""
    sel = [o for o in outcomes if o["config"] == config and o["level"] == level]
    return sum(o["converged"] for o in sel), len(sel), np.array([o["time_s"] for o in sel])


def _ratio(num: np.ndarray, den: np.ndarray) -> str:
    """Ratio of averages, and of medians in parentheses."""
    if not (len(num) and len(den)) or den.mean() <= 0 or np.median(den) <= 0:
        return "-"
    return f"{num.mean() / den.mean():.1f} ({np.median(num) / np.median(den):.1f})"


def peer_report(outcomes: list[dict], peer_trials: int, peer_names: list[str], level_names: tuple[str, ...]) -> str:
    """The "Peers, same trials" section: success, time and comfort per level, ours beside each peer."""
    seeds = {
        lv: {o["seed"] for o in outcomes if o["config"] in peer_names and o["level"] == lv}
        for lv in range(len(level_names))
    }
    same = [o for o in outcomes if o["seed"] in seeds[o["level"]]]
    columns = list(OURS_FOR_PEERS) + peer_names
    short = {c: f"ours, {c}" for c in OURS_FOR_PEERS}
    heads = [short.get(c, c) for c in columns]
    lines = _preamble(peer_trials, peer_names)
    lines += _success_table(same, seeds, columns, heads, level_names)
    lines += _time_table(same, columns, heads, peer_names, level_names)
    lines += _comfort_table(same, seeds, columns, heads, level_names)
    return "\n".join(lines)


def _preamble(peer_trials: int, peer_names: list[str]) -> list[str]:
    lines = [
        "### Peers, same trials",
        "",
        f"The first {peer_trials} trials of every level (the same seeds as above) solved again by two peers; success "
        "is judged by our constraint function alone (every constraint row within its tolerance: 1 mm, 0.2 deg, 1 N, "
        "0.1 N m). The peers get fewer trials than our settings because SLSQP on 192 variables takes seconds per "
        "trial. Times are each solver's own solving time on one core (single-threaded BLAS).",
        "",
        "- **ours**: the unified solver as in the tables above: targets and static balance met with the contact "
        "forces as unknowns, comfort maximised in the constraints' null space; *comfort off*: the same solver "
        "meeting the constraints only (`SolverOptions(optimize_comfort=False)`), the like-for-like setting for placo.",
        f"- **SLSQP**: the same nonlinear program: {PEERS['SLSQP']}; variables scaled as ours, at most 500 iterations.",
    ]
    if "placo" in peer_names:
        lines.append(
            f"- **placo** ({_placo_version()}): {PEERS['placo']}. placo has no unknown contact forces: balance is "
            "the CoM over the support polygon (the soles' hull, refreshed before every QP; the soles' x, y are held "
            "by a weight-1 task at where they stood, so they slide slowly), which with gravity alone is what our "
            "balance with pushing, friction-bounded forces amounts to. Hard foot tasks made placo's QP infeasible "
            "within a few steps, hence soft ones. The QP steps (full steps, regularisation 1e-2, joint limits on) "
            "stop when placo's own task errors are below half our tolerances, or after 100 steps (our solver's "
            "limit too); no comfort is optimised, so its poses are feasible ones, not comfortable ones."
        )
    else:
        lines.append(
            "- **placo**: not installed, so not run "
            "(`pip install --no-deps -r requirements-bench.txt`, see the README)."
        )
    return lines


def _success_table(same, seeds, columns, heads, level_names) -> list[str]:
    lines: list[str] = []
    lines += ["", "Success:", "", "| Max Dev | trials | " + " | ".join(heads) + " |"]
    lines.append("|---|---:|" + "---:|" * len(heads))
    total = {c: [0, 0] for c in columns}
    for lv, name in enumerate(level_names):
        cells = []
        for c in columns:
            ok, n, _ = level_stats(same, c, lv)
            total[c][0] += ok
            total[c][1] += n
            cells.append(f"{ok}/{n}")
        lines.append(f"| {name} | {len(seeds[lv])} | " + " | ".join(cells) + " |")
    lines.append("| all | " + f"{sum(len(v) for v in seeds.values())} | " + " | ".join(
        f"{total[c][0]}/{total[c][1]}" for c in columns) + " |")  # fmt: skip
    return lines


def _time_table(same, columns, heads, peer_names, level_names) -> list[str]:
    lines: list[str] = []
    pairs = [(p, o) for p in peer_names for o in (OURS_FOR_PEERS[:2] if p == "SLSQP" else OURS_FOR_PEERS[::2])]
    tag = {OURS_FOR_PEERS[0]: "p+r", OURS_FOR_PEERS[1]: "p", OURS_FOR_PEERS[2]: "p+r, comfort off"}
    ratio_heads = [f"{p} / ours {tag[o]}" for p, o in pairs]
    lines += [
        "",
        "Time, s: average / median over all these trials (failures included), and the ratio of a peer's average time "
        "to ours (of the medians in parentheses; p+r = physics + reduction, p = physics, no reduction):",
        "",
        "| Max Dev | " + " | ".join(heads) + " | " + " | ".join(ratio_heads) + " |",
        "|---|" + "---:|" * (len(heads) + len(ratio_heads)),
    ]
    for lv in [*range(len(level_names)), None]:
        times = {}
        for c in columns:
            sel = [o for o in same if o["config"] == c and (lv is None or o["level"] == lv)]
            times[c] = np.array([o["time_s"] for o in sel])
        cells = [f"{t.mean():.3f} / {np.median(t):.3f}" if len(t) else "-" for t in times.values()]
        ratios = [_ratio(times[p], times[o]) for p, o in pairs]
        lines.append(f"| {'all' if lv is None else level_names[lv]} | " + " | ".join(cells + ratios) + " |")
    return lines


def _comfort_table(same, seeds, columns, heads, level_names) -> list[str]:
    lines: list[str] = []
    lines += [
        "",
        "Comfort h at the solution (larger is better; 0 = every joint at its neutral value, no load): median over "
        "the trials that every solver met:",
        "",
        "| Max Dev | trials all met | " + " | ".join(heads) + " |",
        "|---|---:|" + "---:|" * len(heads),
    ]
    for lv, name in enumerate(level_names):
        met = [s for s in seeds[lv] if all(
            any(o["seed"] == s and o["config"] == c and o["converged"] for o in same) for c in columns)]  # fmt: skip
        cells = []
        for c in columns:
            h = [o["comfort"] for o in same if o["config"] == c and o["seed"] in met]
            cells.append(f"{np.median(h):.2f}" if h else "-")
        lines.append(f"| {name} | {len(met)} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _placo_version() -> str:
    try:
        from importlib.metadata import version

        return f"placo {version('placo')}"
    except Exception:  # noqa: BLE001 - only a label
        return "placo"
