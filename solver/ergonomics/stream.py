"""The ergonomics of a result file read frame by frame, so a long motion never is in memory at once: a first pass
finds the frames the motion scores need (the NIOSH lift's origin and destination) and computes them, a second
evaluates each frame and appends it to the report JSON and the CSV (both into ``NAME.tmp`` renamed at the end);
the plots are drawn from the few numbers per frame they show."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np

from ..io.files import OutputFile
from ..io.result.frame import Frame
from ..io.result.frame_text import SLOT
from ..io.result.read import ResultStream
from .held import HeldFrames
from .loads import JointLoads
from .manikin import check_fits, resolve_model, strengths, working_area
from .options import ErgoOptions
from .registry import RANKING, SCORES, frame_scores, motion_scores
from .report import HEAD_KEYS, csv_cells, csv_header, csv_row, end_positions, report_head
from .report_text import LoadsText, dumps_filled

PLOTTED_ITEMS = ("back_bend", "neck", "shoulder_l", "shoulder_r")  # the worksheet items plots.plot_back draws
SHOWN = 10  # frames a summary lists in full


class PlotSeries:
    """Per frame only what :mod:`.plots` draws: the plotted scores' values, L4/L5 compression, four worksheet values
    and the percent of strength of every joint (an array row), turned back into a report of the most loaded joints
    at the end."""

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
        scores = {s.name: {key: f[s.name][key] for key in (s.value, "reason") if key in f[s.name]}
                  for s in frame_scores() if s.bands is not None}  # fmt: skip
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
        frames, names = [], [self.joints[j] for j in order]
        for row, values in zip(self.rows, table[:, order].tolist(), strict=True):  # Python floats: no numpy scalars
            loads = {name: {"percent_strength": _number(v)} for name, v in zip(names, values, strict=True)}
            frames.append(dict(row, joint_loads=dict(loads, l4_l5=row["l4_l5"])))
        return {"frames": frames}


def _rank(report: dict) -> tuple[bool, int]:
    """The highest ranking score (REBA) is taken over the converged frames (over all when none converged)."""
    return report["converged"] is not False, report[RANKING][SCORES[RANKING].value] or 0


def _number(v: float) -> float | None:
    return None if math.isnan(v) else float(v)


class _Loads:
    """A frame's joint loads kept as arrays until its report is kept for the summary."""

    __slots__ = ("loads",)

    def __init__(self, loads: JointLoads) -> None:
        self.loads = loads


def _frame_text(report: dict, loads: JointLoads, text: LoadsText) -> str:
    """``json.dumps(report, allow_nan=False)`` of the report :func:`.report.frame_report` builds, its joint loads
    written from their arrays (:mod:`.report_text`)."""
    report["joint_loads"] = SLOT
    written = dumps_filled(report, text(loads))
    if written is None:  # a value holding the slot's text: the dicts as they are
        report["joint_loads"] = loads.as_dict()
        written = json.dumps(report, allow_nan=False)
    return written


class HeldText:
    """A report frame's JSON text and CSV cells, a held pose's (:class:`.held.HeldFrames`) made from the frame
    before's: its text after the head (:data:`.report.HEAD_KEYS`) and its cells after the first three are the
    same."""

    def __init__(self) -> None:
        self.kept = False  # a frame's text and cells are kept
        self._tail = ""
        self._cells: list = []

    def keep(self, report: dict, text: str, cells: list) -> None:
        """Keep the ``text`` and ``cells`` of ``report`` (made in full)."""
        head = _head_text(report)
        self.kept = text.startswith(head)
        self._tail, self._cells = text[len(head) :], cells[len(HEAD_KEYS) :]

    def again(self, report: dict) -> tuple[str, list]:
        """The text and cells of ``report``, a held pose of the frame kept."""
        return _head_text(report) + self._tail, csv_cells([report[key] for key in HEAD_KEYS]) + self._cells


def _head_text(report: dict) -> str:
    """The JSON text of a report frame up to its head's last value."""
    return json.dumps({key: report[key] for key in HEAD_KEYS})[:-1]


def array_csv_cells(report: dict, loads: JointLoads, shown_at: list[int]) -> list:
    """:func:`.report.csv_cells` of the :func:`.report.csv_row` of the report :func:`.report.frame_report` builds
    (the same CSV text), the percent of strength of the joints at ``shown_at`` read from the arrays
    (:func:`rounded_texts`)."""
    row = csv_cells(csv_row(report | {"joint_loads": {"l4_l5": loads.l4_l5}}, []))
    return row + rounded_texts(loads.percent[shown_at])


_TEXT_EXACT = 1e11  # below it round(v, 4) has <= 15 significant digits: its repr is the 4-decimal text, unpadded


def rounded_texts(values: np.ndarray) -> list:
    """``repr(round(v, 4))`` of each value (what the CSV writer writes of the rounded float), "" where not finite,
    formatted in one pass: "%.4f" rounds as round() does (both correctly from the binary value), and stripped of
    its trailing zeros it is the shortest text of a number of <= 15 digits, repr's. Values of 1e11 or more (repr
    may take fewer digits, or an exponent) are rounded one by one (x - x is 0.0 iff x is finite)."""
    if not len(values) or (np.abs(values) >= _TEXT_EXACT).any():
        return [round(v, 4) if v - v == 0.0 else "" for v in values.tolist()]
    text = ("%.4f," * len(values)) % tuple(values.tolist())  # each with its point and 4 decimals
    # each cell's trailing zeros stripped (4 decimals: 4 at most), longest run first; one 0 back after a bare point
    for zeros in ("0000,", "000,", "00,", "0,"):
        text = text.replace(zeros, ",")
    text = text.replace(".,", ".0,")
    cells = text.split(",")[:-1]
    return ["" if "n" in cell else cell for cell in cells] if "n" in text else cells  # "nan", "inf": with an n


class JointColumns:
    """The indices of the CSV's joints in a frame, found again only when the frame's joint names change (the same
    list for every frame of a motion)."""

    def __init__(self, joints: list[str]) -> None:
        self.joints, self.names, self.at = joints, None, []

    def __call__(self, f: Frame) -> list[int]:
        if f.joint_names != self.names:
            self.names, self.at = list(f.joint_names), [f.index[j] for j in self.joints]
        return self.at


def motion_of(stream: ResultStream, options: ErgoOptions) -> tuple[dict[str, dict], Frame]:
    """(the motion scores' values, the first frame) after a quick pass over the file that keeps only the raw
    frames that can start or end a motion score's action: the first, the last and the last of each frame number
    the options name (no frame is built but these)."""
    wanted = {n for score in motion_scores() for n in score.ends(options).values() if n is not None}
    numbers: list = []
    kept: dict[int, tuple] = {}  # position in the file -> (index, raw)
    latest: dict = {}  # a wanted frame number -> the position of its last frame so far
    for index, number, raw in stream.numbered():  # a compact file's lines not parsed but the kept ones
        position = len(numbers)
        numbers.append(number)
        if numbers[-1] in wanted:
            kept.pop(latest.get(numbers[-1]) or -1, None)  # an earlier frame of that number (not the first)
            latest[numbers[-1]] = position
        if position > 1 and position - 1 not in latest.values():
            kept.pop(position - 1, None)  # the previous frame is no longer the last
        kept[position] = (index, raw)
    built: dict[int, Frame] = {}

    def frame(position: int) -> Frame:  # each kept frame built once: a one-frame action's start is its end
        if position not in built:
            built[position] = stream.frame(*kept[position])
        return built[position]

    values = {}
    for score in motion_scores():
        start, end = end_positions(score, numbers, options)
        values[score.name] = score.motion(frame(start), frame(end), options)
    return values, frame(0)


def evaluate_file(result: str | Path, output: Path, options: ErgoOptions, plots: bool) -> dict:
    """Write ``output`` (JSON), the CSV beside it and, if ``plots``, the PNGs; returns the report's entries but
    its frames, ``frames`` = the frames a summary shows (all of a short motion, else the first and the last),
    ``frame_count``, ``highest_reba`` (the frame with the highest REBA, :data:`.registry.RANKING`) and ``written``
    (the paths)."""
    stream = ResultStream(result)
    motion, first = motion_of(stream, options)
    model, note = resolve_model(options.manikin, stream.scenario, stream.path.parent)
    if options.manikin:
        check_fits(model, first, options.manikin)
    area = working_area(model) if model is not None else None
    strength = strengths(first, model)[0]
    joints = [name for name, s in zip(first.joint_names, strength, strict=True) if (np.isfinite(s) & (s > 0)).any()]
    head = report_head(options, note, strengths(first, model)[1], area, motion, str(stream.path), stream.scenario)
    csv_path = output.with_suffix(".csv")
    series, shown, last, highest, count = PlotSeries(), [], None, None, 0
    missed: list[int] = []  # frames that did not converge, and those of them that broke priority 1
    held: list[int] = []
    json_out = OutputFile(output)
    try:
        csv_out = OutputFile(csv_path)
    except BaseException:
        json_out.discard()
        raise
    try:
        out, table = json_out, csv_out  # their write names the file on a full disk
        out.write(json.dumps(head, allow_nan=False)[:-1] + ', "frames": [')
        rows = csv.writer(table, lineterminator="\n")
        parts, text, shown_at = HeldFrames(options, model, area, motion), LoadsText(), JointColumns(joints)
        kept_text = HeldText()
        for f in stream:
            report, loads, _ = parts(f)
            if count == 0:
                rows.writerow(csv_header(report, joints))
            if parts.held and kept_text.kept:
                line, cells = kept_text.again(report)
            else:
                line, cells = _frame_text(report, loads, text), array_csv_cells(report, loads, shown_at(f))
                kept_text.keep(report, line, cells)
            out.write(("\n" if count == 0 else ",\n") + line)
            rows.writerow(cells)
            series.add(report, loads)
            report["joint_loads"] = _Loads(loads)  # a dict of them built only for the frames the summary keeps
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
    try:
        json_out.commit()
    except BaseException:  # a full disk: no temporary CSV left either
        csv_out.discard()
        raise
    csv_out.commit()
    written = [output, csv_path]
    if plots:
        from .plots import write_plots

        written += write_plots(series.report(), output.with_suffix(""))
    shown = shown if count <= SHOWN else [shown[0], last]
    for report in [*shown, last, highest]:
        if report is not None and isinstance(report["joint_loads"], _Loads):
            report["joint_loads"] = report["joint_loads"].loads.as_dict()
    summary = {"frames": shown, "frame_count": count, f"highest_{RANKING}": highest}
    summary["written"] = [str(p) for p in written]
    return head | flags | summary
