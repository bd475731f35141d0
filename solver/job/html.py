"""The job's one-file HTML report, readable offline: inline CSS, plots as inline base64 PNG (matplotlib, Agg). The
verdict of each method on top, then the detail: the inputs, each method's numbers, the plots, the sources."""

from __future__ import annotations

import base64
import io
from html import escape

COLOURS = {0: "#2e7d32", 1: "#f9a825", 2: "#c62828", None: "#546e7a"}
CSS = """body{font-family:sans-serif;margin:2em;max-width:60em;color:#222}
.v{border-left:.6em solid;padding:.4em .8em;margin:.4em 0;background:#f5f5f5}
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:.2em .6em;text-align:right}
th{background:#eee}td:first-child,th:first-child{text-align:left}small{color:#666}"""


def _table(header: list[str], rows: list[list]) -> str:
    head = "".join(f"<th>{escape(str(h))}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{escape(_fmt(v))}</td>" for v in row) + "</tr>" for row in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def _fmt(v) -> str:
    return f"{v:.3g}" if isinstance(v, float) else str(v)


def _png(figure) -> str:
    buf = io.BytesIO()
    figure.savefig(buf, format="png", dpi=90, bbox_inches="tight")
    return f'<img alt="plot" src="data:image/png;base64,{base64.b64encode(buf.getvalue()).decode()}">'


def plots(report: dict) -> list[str]:
    """The plots as <img> tags: the LiFFT load moment over time, the score levels over time."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    times = report["times_s"]
    out = []
    lifft = report["methods"].get("lifft", {})
    if "per_frame" in lifft:
        fig, ax = plt.subplots(figsize=(7, 2.6))
        moment = lifft["per_frame"]["lifft_load_moment_Nm"]
        ax.plot(times, moment)
        ax.plot([times[lifft["plot"]["mark"]]], [lifft["peak_load_moment_Nm"]], "o", color="#c62828")
        ax.set(xlabel="time in the motion (s)", ylabel="N*m", title="load moment about L5/S1 (LiFFT)")
        out.append(_png(fig))
        plt.close(fig)
    seq = report["methods"].get("sequence", {}).get("per_frame", {})
    if seq:
        fig, ax = plt.subplots(figsize=(7, 2.6))
        for name, values in seq.items():
            order = {"reba_risk": ["negligible", "low", "medium", "high", "very high"]}.get(name)
            y = [None if v is None else (order.index(v) + 1 if order else v) for v in values]
            ax.step(times, [float("nan") if v is None else v for v in y], where="post", label=name)
        ax.set(xlabel="time in the motion (s)", ylabel="level (1 = lowest)", title="score levels over the motion")
        ax.legend(fontsize=7)
        out.append(_png(fig))
        plt.close(fig)
    return out


def _verdicts(report: dict) -> str:
    cards = []
    for v in report["verdicts"].values():
        frames = f" <small>(frames {', '.join(map(str, v['frames']))})</small>" if v["frames"] else ""
        cards.append(f'<div class="v" style="border-color:{COLOURS.get(v["severity"])}"><b>{escape(v["title"])}</b>: '
                     f"{escape(v['text'])}{frames}</div>")  # fmt: skip
    return "".join(cards)


def _details(report: dict) -> str:
    parts = ["<h2>The job</h2>", _table(["input", "value"], [[k, v] for k, v in report["job"].items()])]
    lifft = report["methods"].get("lifft", {})
    keys = [k for k in lifft if k not in ("verdict", "per_frame", "plot")]
    if keys:
        parts += ["<h2>LiFFT</h2>", _table(["quantity", "value"], [[k, lifft[k]] for k in keys])]
    seq = report["methods"].get("sequence", {})
    for score in ("rula", "reba", "owas"):
        if seq.get(score):
            rows = [[r["level"], r["frames"], r["seconds"], r["percent_of_motion"], r["percent_of_cycle"]]
                    for r in seq[score]["levels"]]  # fmt: skip
            parts += [f"<h3>{score.upper()}: time at each level (worst frames: "
                      f"{', '.join(map(str, seq[score].get('worst_frames', [])[:10]))})</h3>",
                      _table(["level", "frames", "s", "% of motion", "% of cycle"], rows)]  # fmt: skip
    return "".join(parts)


def html_report(report: dict) -> str:
    """The whole HTML page."""
    title = escape(f"Job: {report['job']['name']}")
    sources = "".join(f"<li><b>{escape(k)}</b>: {escape(v)}</li>" for k, v in report["sources"].items())
    return (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{title}</title><style>{CSS}</style></head><body>"
            f"<h1>{title}</h1><p>{len(report['frames'])} frames, {report['motion_time_s']:.2f} s of motion per "
            f"{report['job']['cycle_time_s']:g} s cycle; {report['job']['repetitions_per_shift']} cycles per "
            f"{report['job']['shift_h']:g} h shift. Motion: {escape(report['motion_file'])}</p>"
            f"<h2>Verdicts</h2>{_verdicts(report)}{_details(report)}<h2>Plots</h2>{''.join(plots(report))}"
            f"<h2>Sources</h2><ul>{sources}</ul></body></html>\n")  # fmt: skip
