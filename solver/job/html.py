"""The job's one-file HTML report, readable offline: inline CSS, plots and pictures as inline base64 PNG
(matplotlib, Agg). The verdict of each method on top, then the job's inputs and, per method, its detail tables
(:meth:`.base.Method.detail`), its plot (its result's ``plot``) and a picture of each frame driving its verdict
with its lever arms (:mod:`.picture`); then the sources. Nothing here names a method: a new one needs no change."""

from __future__ import annotations

import base64
import io
from html import escape

from ..io.result.frame import Frame
from .registry import METHODS

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


def _img(png: bytes, alt: str) -> str:
    return f'<img alt="{escape(alt)}" src="data:image/png;base64,{base64.b64encode(png).decode()}">'


def _png(figure) -> bytes:
    buf = io.BytesIO()
    figure.savefig(buf, format="png", dpi=90, bbox_inches="tight")
    return buf.getvalue()


def plot(times: list[float], result: dict) -> str:
    """A method's plot over the motion's time as an <img> tag ("" without one): ``line`` (its per-frame columns,
    the ``marks`` dotted) or ``levels`` (each per-frame column as steps, named levels by their ``order``)."""
    spec, columns = result.get("plot"), result.get("per_frame", {})
    if not spec or not columns:
        return ""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 2.6))
    if spec["kind"] == "line":
        for name in spec["y"]:
            ax.plot(times, columns[name], label=name)
        for name, i in zip(spec["y"], spec.get("marks", []), strict=False):
            ax.plot([times[i]], [columns[name][i]], "o", color="#c62828")
        ylabel = spec.get("label", "")
    else:
        for name, values in columns.items():
            order = spec.get("order", {}).get(name)
            y = [float("nan") if v is None else (order.index(v) + 1 if order else v) for v in values]
            ax.step(times, y, where="post", label=name)
        ylabel = "level (1 = lowest)"
    ax.set(xlabel="time in the motion (s)", ylabel=ylabel, title=spec.get("title", ""))
    if len(columns) > 1 or spec["kind"] != "line":
        ax.legend(fontsize=7)
    try:
        return _img(_png(fig), spec.get("title", "plot"))
    finally:
        plt.close(fig)


def pictures(title: str, result: dict, frames: dict[int, Frame]) -> str:
    """A side and front view of each frame driving the method's verdict, with its lever arms at that frame."""
    from .picture import frame_png

    out = []
    for number in result["verdict"]["frames"]:
        if number in frames:
            levers = [v for v in result.get("levers", []) if v["frame"] == number]
            names = "; ".join(f"{v['label']} {v['length_m']:.2f} m" for v in levers)
            caption = f"{title}: frame {number}" + (f" ({names})" if names else "")
            out.append(f"<figure>{_img(frame_png(frames[number], caption, levers), caption)}"
                       f"<figcaption><small>{escape(caption)}</small></figcaption></figure>")  # fmt: skip
    return "".join(out)


def _verdicts(verdicts: dict) -> str:
    cards = []
    for v in verdicts.values():
        frames = f" <small>(frames {', '.join(map(str, v['frames']))})</small>" if v["frames"] else ""
        task = f" <small>(task {escape(v['task'])})</small>" if v.get("task") else ""
        cards.append(f'<div class="v" style="border-color:{COLOURS.get(v["severity"])}"><b>{escape(v["title"])}</b>: '
                     f"{escape(v['text'])}{task}{frames}</div>")  # fmt: skip
    return "".join(cards)


def _methods(task: dict, frames: dict[int, Frame], level: int = 2) -> str:
    """Per method of one task: its detail tables, its plot over the task's motion, its driving frames' pictures."""
    parts = []
    for name, result in task["methods"].items():
        method = METHODS[name]
        anchor = name if level == 2 else f"{_slug(task['name'])}-{name}"  # one task: the method's name, as before
        parts.append(f'<h{level} id="{escape(anchor)}">{escape(method.title)}</h{level}>')
        parts += [f"<h{level + 1}>{escape(head)}</h{level + 1}>{_table(header, rows)}"
                  for head, header, rows in method.detail(result)]  # fmt: skip
        parts += [plot(task["times_s"], result), pictures(method.title, result, frames)]
    return "".join(parts)


def _totals(report: dict) -> str:
    """The job's result of each method over its tasks: its tables and the per-task table it adds up."""
    parts = ["<h2>The job's totals over its tasks</h2>"]
    for name, result in report["methods"].items():
        method = METHODS[name]
        parts.append(f"<h3>{escape(method.title)}</h3>")
        parts += [f"<h4>{escape(head)}</h4>{_table(header, rows)}" for head, header, rows in method.detail(result)]
        rows = result.get("per_task") or []
        if rows:
            parts.append(_table(list(rows[0]), [list(r.values()) for r in rows]))
    return "".join(parts)


def _slug(name: str) -> str:
    """A task's name as an HTML id (no spaces)."""
    return "task-" + "-".join(name.split())


def _inputs(job: dict) -> list[list]:
    return [[k, v] for k, v in job.items() if k != "tasks"]


def html_report(report: dict, frames: list[Frame] | None = None, task_frames: list[list[Frame]] | None = None) -> str:
    """The whole HTML page; with the motion's ``frames`` (one task) or each task's ``task_frames``, the pictures of
    the driving frames. A job of several tasks: its verdicts and totals, then a section per task."""
    title = escape(f"Job: {report['job']['name']}")
    tasks = report["tasks"]
    task_frames = task_frames or [frames or []] + [[] for _ in tasks[1:]]
    by_number = [{f.number: f for f in fs} for fs in task_frames]
    sources = "".join(f"<li><b>{escape(k)}</b>: {escape(v)}</li>" for k, v in report["sources"].items())
    job = report["job"]
    if len(tasks) == 1:
        head = (f"{len(report['frames'])} frames, {report['motion_time_s']:.2f} s of motion per "
                f"{job['cycle_time_s']:g} s cycle; {job['repetitions_per_shift']} cycles per {job['shift_h']:g} h "
                f"shift. Motion: {escape(report['motion_file'])}")  # fmt: skip
        body = _methods(tasks[0] | {"methods": report["methods"]}, by_number[0])  # the job's: a caller may add
    else:
        head = (f"{len(tasks)} tasks, {report['motion_time_s']:.2f} s of motion per {job['cycle_time_s']:g} s cycle; "
                f"{job['repetitions_per_shift']} cycles per {job['shift_h']:g} h shift.")  # fmt: skip
        body = _totals(report)
        for task, numbers in zip(tasks, by_number, strict=True):
            inputs = [[k, v] for k, v in task["inputs"].items()] + [["motion file", task["motion_file"]]]
            notes = "".join(f"<p><small>{escape(n)}</small></p>" for n in task["notes"])
            body += (f'<h2 id="{escape(_slug(task["name"]))}">Task: {escape(task["name"])}</h2>{notes}'
                     f"{_verdicts(task['verdicts'])}{_table(['input', 'value'], inputs)}"
                     f"{_methods(task, numbers, 3)}")  # fmt: skip
    return (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{title}</title><style>{CSS}</style></head><body>"
            f"<h1>{title}</h1><p>{head}</p><h2>Verdicts</h2>{_verdicts(report['verdicts'])}"
            f"<h2>The job</h2>{_table(['input', 'value'], _inputs(job))}{body}"
            f"<h2>Sources</h2><ul>{sources}</ul></body></html>\n")  # fmt: skip
