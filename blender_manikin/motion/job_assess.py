"""A job assessed from a baked motion (plain Python, no bpy): what the Job panel's Assess Job and Write Report run.

A bake keeps, in each frame's sidebar entry (:mod:`.frame_store`), the frame's pose: its joint values, contact
wrenches, loads and status (:func:`pose_part`, about 1 kB a frame). :func:`frames_of` turns those back into the
solver's typed frames (:func:`solver.io.result.frame.frame_of_pose`, as a result file would give them); the job's
inputs are checked by the job file's own reader (:func:`solver.job.read_job`), and :func:`assess` runs
:func:`solver.job.evaluate_job`, every method of its registry, exactly as ``manikin job`` does. No second
implementation: the panel shows whatever methods the registry has.

The report (:func:`html_of`) is the job command's one-file HTML. Blender's Python has no matplotlib: there the
plots and the driving frames' pictures are left out and the report says so; with matplotlib they are drawn.
"""

from __future__ import annotations

import json
import tempfile
from dataclasses import dataclass, replace
from html import escape
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ...solver.errors import ManikinError, UsageError

if TYPE_CHECKING:
    from ...solver import Model, Result
    from ...solver.io.result.frame import Frame
    from ...solver.job import Job

POSE_KEY = "pose"  # a frame entry's part the job reads
HANDS = {"hand_r": "right", "hand_l": "left"}  # the TCPs a job's load can hang at, by the job file's word
LABELS = {  # the job file's keys as the panel names them, for its one-line errors
    "work.cycle_time": "Cycle time (s)",
    "work.repetitions": "Cycles per shift",
    "work.shift": "Shift (h)",
    "work.lifts_per_cycle": "Lifts per cycle",
    "load.mass": "Load (kg)",
    "load.hands": "Hands",
}
NO_PLOTS = (
    "Written in Blender, whose Python has no matplotlib: the plots over the motion and the pictures of the "
    "driving frames are left out (the tables and verdicts are complete); <code>manikin job</code> draws them."
)


def _numbers(values, digits: int = 9) -> list[float]:
    """Each value rounded to ``digits`` significant digits, as its shortest text of those would read back."""
    text = f"{{:.{digits}g}}".format  # one format for all (the same text as f"{v:.9g}")
    floats = values.tolist() if isinstance(values, np.ndarray) else map(float, values)  # Python floats: the same
    return [float(text(v)) for v in floats]


def pose_part(result: Result) -> dict:
    """What the job needs of a baked frame beyond the sidebar's entry: joint values (rad, m), contact wrenches
    (point m, force N, moment N*m), loads (point m, force N) and whether the solve held."""
    state, problem = result.state, result.problem
    contacts = [[c["tcp"], _numbers(c["point"]), _numbers(c["force"]), _numbers(c["moment"])] for c in result.contacts]
    loads = [[ld.tcp.name, _numbers(p), _numbers(ld.force)]
             for ld, p in zip(problem.loads, state.statics.load_points, strict=True)]  # fmt: skip
    return dict(theta=_numbers(result.theta), contacts=contacts, loads=loads, broken=list(result.broken))


def stored_poses(entries: list[dict]) -> list[dict]:
    """The baked entries that hold a pose, in frame order; none when the bake was made before poses were kept."""
    return sorted((e for e in entries if isinstance(e.get(POSE_KEY), dict)), key=lambda e: e["frame"])


def frames_of(entries: list[dict], model: Model) -> list[Frame]:
    """The solver's typed frames of the baked ``entries`` (each with its ``pose``), posed on ``model``."""
    from ...solver.io.result.frame import frame_of_pose

    frames = []
    for e in entries:
        pose = e[POSE_KEY]
        theta = np.asarray(pose["theta"], dtype=float)
        if len(theta) != model.n:
            raise ManikinError(f"frame {e['frame']}: the baked pose has {len(theta)} joints, the manikin {model.n}: "
                               "bake the motion again")  # fmt: skip
        status = dict(number=int(e["frame"]), converged=bool(e["converged"]), unmet=tuple(e.get("unmet", ())),
                      broken=tuple(pose.get("broken", ())))  # fmt: skip
        contacts = [(t, np.array(p), np.array(f), np.array(m)) for t, p, f, m in pose["contacts"]]
        loads = [(t, np.array(p), np.array(f)) for t, p, f in pose["loads"]]
        frames.append(frame_of_pose(model, model.forward(theta), status, contacts, loads))
    return frames


def scene_load(entries: list[dict], gravity: float = 9.81) -> tuple[float, str] | None:
    """The load the baked hands hold (kg, "both" / "right" / "left") from the first frame's loads at the hands, or
    None when they hold none: the panel's default."""
    hands: dict[str, float] = {}
    for tcp, _, force in entries[0][POSE_KEY]["loads"] if entries else ():
        if tcp in HANDS:
            hands[tcp] = hands.get(tcp, 0.0) + float(np.linalg.norm(force)) / gravity
    held = [t for t, kg in hands.items() if kg > 0.0]
    if not held:
        return None
    return sum(hands.values()), "both" if len(held) == 2 else HANDS[held[0]]


@dataclass(frozen=True)
class Work:
    """The job's inputs the panel sets: cycle time s, cycles per shift, shift h, lifts per cycle, load kg, hands."""

    cycle_time: float
    repetitions: int
    shift: float
    lifts_per_cycle: int
    load_mass: float
    hands: str  # both | right | left

    def toml(self, name: str, fps: float) -> str:
        """The job file these inputs make (its motion a placeholder result beside it)."""
        return (f"name = {json.dumps(name)}\n[motion]\nresult = \"motion.json\"\nfps = {fps!r}\n"
                f"[work]\ncycle_time = {self.cycle_time!r}\nrepetitions = {self.repetitions}\nshift = {self.shift!r}\n"
                f"lifts_per_cycle = {self.lifts_per_cycle}\n[load]\nmass = {self.load_mass!r}\n"
                f"hands = {json.dumps(self.hands)}\n")  # fmt: skip


def job_of(work: Work, name: str, fps: float, where: str) -> Job:
    """The job of ``work`` checked by the job file's reader (one UsageError line naming the panel's field);
    ``where`` names the motion (the armature and .blend) in the report."""
    from ...solver.job import read_job

    with tempfile.TemporaryDirectory(prefix="manikin-job-") as folder:
        path = Path(folder) / "job.toml"
        path.write_text(work.toml(name, fps), encoding="utf-8")
        (Path(folder) / "motion.json").write_text("", encoding="utf-8")
        try:
            job = read_job(path)
        except UsageError as exc:
            raise UsageError(_panel_words(str(exc).removeprefix(f"{path}: "))) from None
    return replace(job, path=Path(where), result=Path(where))


def _panel_words(text: str) -> str:
    for key, label in LABELS.items():
        if text.startswith(key + ":"):
            return label + text[len(key) :]
    return text


def assess(entries: list[dict], model: Model, work: Work, name: str, fps: float,
           where: str) -> tuple[dict, list[Frame]]:  # fmt: skip
    """(the job report of the baked ``entries`` (:func:`solver.job.evaluate_job`), the typed frames it rated);
    ``where`` names the motion. A bad input or no stored pose: one ManikinError line."""
    from ...solver.io.result.read import ResultFile
    from ...solver.job import evaluate_job

    posed = stored_poses(entries)
    if not posed:
        raise ManikinError("no baked motion: bake the motion first (Motion > Bake Motion)")
    job = job_of(work, name, fps, where)
    frames = frames_of(posed, model)
    try:
        return evaluate_job(job, ResultFile(Path(where), None, frames), model), frames
    except UsageError as exc:  # the motion longer than the cycle: named as the panel names the field
        raise UsageError(_panel_words(str(exc).removeprefix(f"{job.path}: "))) from None


def verdict_rows(report: dict) -> list[dict]:
    """One row per method, in the registry's order: title, verdict line, severity (0/1/2/None), driving frames."""
    return [dict(name=name, title=v["title"], text=v["text"], severity=v["severity"], frames=list(v["frames"]))
            for name, v in report["verdicts"].items()]  # fmt: skip


def has_matplotlib() -> bool:
    """Whether this Python can draw the report's plots and pictures (a real Blender's cannot)."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return False
    return True


def html_of(report: dict, frames: list[Frame], plots: bool | None = None) -> str:
    """The job command's one-file HTML of ``report``; without matplotlib (``plots`` None: as found) no plots and no
    pictures, and a line saying so (as when drawing them fails: the verdicts and tables still go out)."""
    from ...solver.job.html import html_report

    note = NO_PLOTS
    if plots is None:
        plots = has_matplotlib()
    if plots:
        try:
            return html_report(report, frames)
        except Exception as exc:  # noqa: BLE001 (a plotting library's failure must not cost the report)
            note = f"The plots and pictures could not be drawn ({type(exc).__name__}: {exc}); they are left out."
    bare = report | {"methods": {k: {n: v for n, v in r.items() if n != "plot"} for k, r in report["methods"].items()}}
    text = html_report(bare, None)
    return text.replace("<h2>Verdicts</h2>", f"<p><small>{escape(note) if note is not NO_PLOTS else note}</small></p>"
                        "<h2>Verdicts</h2>", 1)  # fmt: skip
