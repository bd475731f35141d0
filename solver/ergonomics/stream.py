"""The ergonomics of a result file read frame by frame, so a long motion never is in memory at once: a first pass
finds the NIOSH lift's origin and destination frames, a second evaluates each frame and appends it to the report
JSON and the CSV (both into ``NAME.tmp`` renamed at the end); the plots are drawn from the few numbers per frame
they show."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np

from ..errors import UsageError
from ..io.files import OutputFile
from ..io.result.read import ResultStream
from . import niosh
from .loads import JointLoads
from .manikin import check_fits, resolve_model, strengths, working_area
from .options import ErgoOptions
from .report import csv_cells, csv_header, csv_row, frame_report, report_head, worksheet_items

PLOTTED_ITEMS = ("back_bend", "neck", "shoulder_l", "shoulder_r")  # the worksheet items plots.plot_back draws
SHOWN = 10  # frames a summary lists in full


class PlotSeries:
    """Per frame only what :mod:`.plots` draws: scores, L4/L5 compression, four worksheet values and the percent
    of strength of every joint (an array row), turned back into a report of the most loaded joints at the end."""

    def __init__(self) -> None:
        self.joints: list[str] | None = None
        self.percent: list[np.ndarray] = []
        self.rows: list[dict] = []

    def add(self, f: dict, arrays: JointLoads | None = None) -> None:
        """One frame's report (:func:`.report.frame_report`), or :func:`.report.frame_parts`'s report and loads."""
        loads = f["joint_loads"] if arrays is None else {"l4_l5": arrays.l4_l5}
        if self.joints is None:
            self.joints = [j for j in loads if j != "l4_l5"] if arrays is None else list(arrays.names)
        if arrays is None:
            p = [loads[j]["percent_strength"] for j in self.joints]
            self.percent.append(np.array([math.nan if v is None else v for v in p], dtype=float))
        else:  # as_dict's null (not finite) is NaN here
            self.percent.append(np.where(np.isfinite(arrays.percent), arrays.percent, math.nan))
        scores = {k: {key: f[k][key] for key in ("score", "reason") if key in f[k]} for k in ("rula", "reba")}
        items = {k: {"value": f["worksheet"][k]["value"], "level": f["worksheet"][k]["level"]} for k in PLOTTED_ITEMS
                 if k in f["worksheet"]}  # fmt: skip
        compression = {"compression": loads["l4_l5"].get("compression")}
        status = dict(frame=f["frame"], converged=f["converged"], status=f.get("status"))
        self.rows.append(dict(status, worksheet=items, l4_l5=compression, **scores))

    def report(self, top: int = 8) -> dict:
        """A report with ``frames`` holding these numbers and the ``top`` most loaded joints (as plots picks them)."""
        table = np.array(self.percent).reshape(len(self.percent), -1)
        seen = ~np.isnan(table).all(axis=0)
        peak = np.where(seen, np.nanmax(np.where(np.isnan(table), 0.0, table), axis=0, initial=0.0), -1.0)
        order = [j for j in np.argsort(-peak, kind="stable") if seen[j]][:top]
        frames = []
        for i, row in enumerate(self.rows):
            loads = {self.joints[j]: {"percent_strength": _number(table[i, j])} for j in order}
            frames.append(dict(row, joint_loads=dict(loads, l4_l5=row["l4_l5"])))
        return {"frames": frames}


def _rank(report: dict) -> tuple[bool, int]:
    """The highest REBA is taken over the converged frames (over all when none converged)."""
    return report["converged"] is not False, report["reba"]["score"] or 0


def _number(v: float) -> float | None:
    return None if math.isnan(v) else float(v)


def lift_of(stream: ResultStream, options: ErgoOptions) -> tuple[dict, object]:
    """(the NIOSH lift, the first frame) after a quick pass over the file (no frame built but these two)."""
    first = last = origin = destination = None
    numbers = []
    for index, raw in stream.raw():
        number = raw.get("frame", 1) if isinstance(raw, dict) else None
        numbers.append(number)
        first = first or (index, raw)
        last = (index, raw)
        if options.origin is not None and number == options.origin:
            origin = (index, raw)
        if options.destination is not None and number == options.destination:
            destination = (index, raw)
    for what, asked, found in (("origin", options.origin, origin), ("destination", options.destination, destination)):
        if asked is not None and found is None:
            listed = ", ".join(map(str, numbers)) if len(numbers) <= 6 else f"{numbers[0]}, ..., {numbers[-1]}"
            raise UsageError(f"{what} {asked}: not a frame of the result (its frames: {listed})")
    origin, destination = origin or first, destination or last
    a = stream.frame(*origin)
    b = a if destination[0] == origin[0] else stream.frame(*destination)
    return niosh.lift_between(a, b, options), stream.frame(*first)


def evaluate_file(result: str | Path, output: Path, options: ErgoOptions, plots: bool) -> dict:
    """Write ``output`` (JSON), the CSV beside it and, if ``plots``, the PNGs; returns the report's entries but
    its frames, ``frames`` = the frames a summary shows (all of a short motion, else the first and the last),
    ``frame_count``, ``highest_reba`` (the frame with the highest REBA) and ``written`` (the paths)."""
    stream = ResultStream(result)
    lift, first = lift_of(stream, options)
    model, note = resolve_model(options.manikin, stream.scenario, stream.path.parent)
    if options.manikin:
        check_fits(model, first, options.manikin)
    area = working_area(model) if model is not None else None
    strength = strengths(first, model)[0]
    joints = [name for name, s in zip(first.joint_names, strength, strict=True) if (np.isfinite(s) & (s > 0)).any()]
    head = report_head(options, note, strengths(first, model)[1], area, lift, str(stream.path), stream.scenario)
    csv_path = output.with_suffix(".csv")
    series, shown, last, highest, count = PlotSeries(), [], None, None, 0
    missed: list[int] = []  # frames that did not converge, and those of them that broke priority 1
    held: list[int] = []
    json_out = OutputFile(output)
    csv_out = OutputFile(csv_path)
    try:
        out, table = json_out.stream, csv_out.stream
        out.write(json.dumps(head, allow_nan=False)[:-1] + ', "frames": [')
        rows = csv.writer(table, lineterminator="\n")
        for f in stream:
            report = frame_report(f, options, model, area, lift)[0]
            if count == 0:
                items = worksheet_items(report)
                rows.writerow(csv_header(items, joints))
            out.write(("\n" if count == 0 else ",\n") + json.dumps(report, allow_nan=False))
            rows.writerow(csv_cells(csv_row(report, items, joints)))
            series.add(report)
            shown, last = shown + [report] if len(shown) < SHOWN else shown, report
            if report["converged"] is False:
                missed.append(report["frame"])
                held += [report["frame"]] if report["status"].startswith("NOT held") else []
            if highest is None or _rank(report) > _rank(highest):
                highest = report
            count += 1
        flags = dict(not_converged=missed, not_held=held)
        out.write("\n], " + json.dumps(flags)[1:] + "\n")
    except BaseException:  # an error or Ctrl-C: no half report left behind, the old one (if any) kept
        json_out.discard()
        csv_out.discard()
        raise
    json_out.commit()
    csv_out.commit()
    written = [output, csv_path]
    if plots:
        from .plots import write_plots

        written += write_plots(series.report(), output.with_suffix(""))
    shown = shown if count <= SHOWN else [shown[0], last]
    summary = dict(frames=shown, frame_count=count, highest_reba=highest, written=[str(p) for p in written])
    return head | flags | summary
