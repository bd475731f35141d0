"""A study's summary plots (PNG, matplotlib figures without pyplot): who can do the task, and how hard it is.

* ``feasibility.png``: per scenario and parameter, the share of runs (manikins, and the other parameters' values)
  that converged (every target reached in balance) at each value of the parameter; failed runs are left out of
  the share (they say nothing about the body). A scenario without parameters is one bar.
* ``scores.png``: per manikin, the peak of each score with one number per frame (RULA, REBA: :func:`.groups.panels`),
  L4/L5 compression (N) and percent of joint strength of each of its runs (filled: converged, open: not), with the
  limits of the worksheet (NIOSH 3400 / 6400 N; 30 / 60 %).
* ``envelopes.png`` (a study with an ``[envelope]``): per manikin and setting (hand, load, feet, sole scale), the
  mean reach from the shoulder in the set conditions (bar; its range over the directions as a line) and without
  balance (a tick), and the envelope's volume (bar) and without balance (a tick).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ..io.files import open_output
from .groups import panels as score_panels

if TYPE_CHECKING:
    from .envelope_spec import EnvelopeStudy

FEASIBILITY, SCORES, ENVELOPES = "feasibility.png", "scores.png", "envelopes.png"
COLOURS = ("#2f6fa8", "#d9731a", "#3a9a3a", "#8e4fb0", "#c8372d", "#7a7a7a")


def _save(fig, path: Path) -> Path:
    with open_output(path, binary=True) as fh:
        fig.savefig(fh, format="png", dpi=110)
    return path


def _key(value) -> tuple:
    """Sort numbers by value, anything else by its text after them."""
    return (0, value, "") if isinstance(value, int | float) and not isinstance(value, bool) else (1, 0, str(value))


def shares(rows: list[dict], scenario: str, parameter: str | None) -> list[tuple[object, float, int]]:
    """(parameter value, share converged %, runs counted) of the scenario's runs that did not fail."""
    counted: dict = {}
    for row in rows:
        if row["scenario"] != scenario or row.get("status") == "failed":
            continue
        value = row.get(f"p_{parameter}") if parameter else scenario
        ok, n = counted.get(repr(value), (value, 0, 0))[1:]
        counted[repr(value)] = (value, ok + bool(row.get("converged")), n + 1)
    out = [(value, 100.0 * ok / n, n) for value, ok, n in counted.values()]
    return sorted(out, key=lambda item: _key(item[0]))


def feasibility(path: Path, rows: list[dict], panels: list[tuple[str, str | None]]) -> Path:
    """The share of runs that can do the task per parameter value; ``panels``: (scenario, parameter or None)."""
    from matplotlib.figure import Figure

    cols = min(3, max(1, len(panels)))
    lines = (len(panels) + cols - 1) // cols
    fig = Figure(figsize=(4.2 * cols, 3.2 * lines), layout="constrained")
    for i, (scenario, parameter) in enumerate(panels):
        ax = fig.add_subplot(lines, cols, i + 1)
        data = shares(rows, scenario, parameter)
        labels = [f"{v:g}" if isinstance(v, float) else str(v) for v, _, _ in data]
        bars = ax.bar(range(len(data)), [s for _, s, _ in data], color="#4a7fb5")
        for bar, (_, share, n) in zip(bars, data, strict=True):
            ax.annotate(f"{share:.0f} %\nn={n}", (bar.get_x() + bar.get_width() / 2, share), ha="center",
                        va="bottom", fontsize=7, xytext=(0, 2), textcoords="offset points")  # fmt: skip
        ax.set_xticks(range(len(data)), labels, fontsize=8, rotation=30 if len(data) > 6 else 0)
        ax.set_ylim(0, 118)
        ax.set_ylabel("can do it (converged), %", fontsize=8)
        ax.set_title(f"{scenario}: by {parameter}" if parameter else scenario, fontsize=9)
        if parameter:
            ax.set_xlabel(parameter, fontsize=8)
    fig.suptitle("Share of the runs that can do the task (failed runs left out)", fontsize=10)
    return _save(fig, path)


def scores(path: Path, rows: list[dict], manikins: list[str], record: tuple[str, ...]) -> Path | None:
    """Each run's peak scores by manikin (the panels of the recorded groups), a colour per scenario side by side,
    open marks for runs that did not converge; None if no score was recorded."""
    from matplotlib.figure import Figure

    panels = [p[1:] for p in score_panels() if p[0] in record]
    if not panels:
        return None
    scenarios = list(dict.fromkeys(r["scenario"] for r in rows))
    width = max(6.0, min(24.0, 0.35 * len(manikins) * max(1, len(scenarios) / 2) + 2.0))
    fig = Figure(figsize=(width, 2.4 * len(panels) + 0.8), layout="constrained")
    place = {name: i for i, name in enumerate(manikins)}
    many = len(manikins) > 8
    for k, (column, title, limits) in enumerate(panels):
        ax = fig.add_subplot(len(panels), 1, k + 1)
        for j, scenario in enumerate(scenarios):
            _scenario_points(ax, rows, scenario, column, place, (j - (len(scenarios) - 1) / 2) * 0.6 / len(scenarios),
                             COLOURS[j % len(COLOURS)])  # fmt: skip
        for limit, colour in zip(limits, ("#d9a400", "#c8372d"), strict=False):
            ax.axhline(limit, color=colour, lw=1, ls="--")
        ax.set_title(title, fontsize=9, loc="left")
        labels = manikins if k == len(panels) - 1 else [""] * len(manikins)
        ax.set_xticks(range(len(manikins)), labels, rotation=60 if many else 0, fontsize=7,
                      ha="right" if many else "center")  # fmt: skip
        ax.set_xlim(-0.6, len(manikins) - 0.4)
        if k == 0 and ax.get_legend_handles_labels()[0]:  # no legend where no run has a score (all failed)
            ax.legend(fontsize=7, loc="upper right", title="open: not converged", title_fontsize=7)
    fig.suptitle("Peak scores of each run, by manikin", fontsize=10)
    return _save(fig, path)


def _scenario_points(ax, rows: list[dict], scenario: str, column: str, place: dict, shift: float, colour: str) -> None:
    """One scenario's runs in one panel: filled where converged, open where not."""
    mine = [r for r in rows if r["scenario"] == scenario and r.get(column) is not None and r["manikin"] in place]
    for ok in (True, False):
        pts = [(place[r["manikin"]] + shift, r[column]) for r in mine if bool(r.get("converged")) == ok]
        if pts:
            style = dict(color=colour) if ok else dict(facecolors="none", edgecolors=colour)
            ax.scatter(*zip(*pts, strict=True), s=16, label=scenario if ok else None, **style)


def _setting(row: dict) -> str:
    """An envelope row's settings in a few words: "right, 10 kg, step" (and the sole scale when not 1)."""
    text = f"{row['p_hand']}, {row['p_load_kg']:g} kg, {row['p_feet']}"
    return text + (f", soles x{row['p_sole_scale']:g}" if row["p_sole_scale"] != 1.0 else "")


def envelopes(path: Path, rows: list[dict], manikins: list[str]) -> Path:
    """The envelope rows' mean reach and volume by manikin, a colour per setting (see the module docstring)."""
    from matplotlib.figure import Figure

    done = [r for r in rows if r.get("status") != "failed" and r.get("balanced_mean_m") is not None]
    settings = list(dict.fromkeys(_setting(r) for r in done))
    place = {name: i for i, name in enumerate(manikins)}
    width = max(6.0, min(24.0, 0.45 * len(manikins) * max(1, len(settings)) + 2.5))
    fig = Figure(figsize=(width, 6.0), layout="constrained")
    panels = (("balanced_mean_m", "kinematic_mean_m", "mean reach from the shoulder, m"),
              ("volume_balanced_m3", "volume_kinematic_m3", "envelope volume, m$^3$"))  # fmt: skip
    step = 0.8 / max(1, len(settings))
    for k, (column, without, title) in enumerate(panels):
        ax = fig.add_subplot(2, 1, k + 1)
        for j, setting in enumerate(settings):
            mine = [r for r in done if _setting(r) == setting and r["manikin"] in place]
            x = [place[r["manikin"]] + (j - (len(settings) - 1) / 2) * step for r in mine]
            colour = COLOURS[j % len(COLOURS)]
            ax.bar(x, [r[column] for r in mine], width=step * 0.9, color=colour, label=setting)
            ax.scatter(x, [r[without] for r in mine], marker="_", s=120, color="black",
                       label="without balance" if j == 0 else None)  # fmt: skip
            if k == 0:
                low = [r[column] - r["balanced_min_m"] for r in mine]
                high = [r["balanced_max_m"] - r[column] for r in mine]
                ax.errorbar(x, [r[column] for r in mine], yerr=[low, high], fmt="none", ecolor="#333333", lw=0.8)
        ax.set_title(title + (" (line: shortest to longest direction)" if k == 0 else ""), fontsize=9, loc="left")
        many = len(manikins) > 8
        ax.set_xticks(range(len(manikins)), manikins if k == 1 else [""] * len(manikins), fontsize=7,
                      rotation=60 if many else 0, ha="right" if many else "center")  # fmt: skip
        ax.set_xlim(-0.6, len(manikins) - 0.4)
        if k == 0 and ax.get_legend_handles_labels()[0]:  # no legend where no run has a score (all failed)
            ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    fig.suptitle("Reach envelopes by manikin (bars: in the set conditions)", fontsize=10)
    return _save(fig, path)


def write_plots(folder: Path, rows: list[dict], panels: list, manikins: list[str], record: tuple,
                envelope: EnvelopeStudy | None = None) -> list[Path]:  # fmt: skip
    """The plots in ``folder`` (feasibility with scenario ``panels``, scores with ``record``ed groups, envelopes
    with an ``envelope``); [] without matplotlib (the rows are all there still)."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return []
    out = [feasibility(folder / FEASIBILITY, rows, panels)] if panels else []
    drawn = scores(folder / SCORES, rows, manikins, record)
    out += [drawn] if drawn else []
    if envelope is not None:
        mine = [r for r in rows if r["scenario"] == envelope.name]
        out.append(envelopes(folder / ENVELOPES, mine, list(dict.fromkeys(r["manikin"] for r in mine))))
    return out
