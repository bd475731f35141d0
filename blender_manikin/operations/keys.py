"""A generated motion's result file keyed in the scene (bpy): the manikin's joints (as Bake Motion keys them: one
F-curve per bone channel, the sidebar's per-frame entries and score curves, so the Motion Ergonomics panel reads
it), and each object of the operations where the plan has it: resting where it lies, held: following the solved
hands (the plan's offset from them at the grasp), keeping its rotation (operations never turn objects).
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import bpy
import numpy as np

from ...solver.io.result.frame import Frame
from ...solver.io.result.read import ResultStream
from ..motion.bake import Baker, FrameRecord
from ..motion.frame_store import ergonomics_part, result_part
from ..motion.report import MotionReport
from ..scene import keyframes
from ..scene.armature import model_of
from ..scene.schema import FILE_KEY, PRESET_KEY
from .objects import box_of

GROUP = "Object Transforms"


class FileReport(MotionReport):
    """The bake's report filled from a result file's frames instead of live Results (the sidebar's store only)."""

    def add_frame(self, record: FrameRecord, f: Frame, raw: dict) -> None:
        """One frame read from the file (``raw``: its JSON, for the solve's status)."""
        ergo, loads, _ = self._parts(f)  # a held pose's ergonomics computed once
        self.ends = [self.ends[0] if self.ends else f, f]
        self.kept.append({s.name: s.keep(f) for s in self.motions})
        if self.store is not None:
            result = SimpleNamespace(
                broken=list(raw.get("broken", [])), shortfall=dict(raw.get("shortfall", {})),
                comfort=float(raw.get("comfort", 0.0)), comfort_parts=dict(raw.get("comfort_terms", {})),
                contacts=[dict(tcp=tcp, force=force) for tcp, _, force, _ in f.contacts],
                state=SimpleNamespace(statics=SimpleNamespace(axis_loads=lambda: loads.axis_moment)),
            )  # fmt: skip
            ergo_l4 = ergo | {"joint_loads": {"l4_l5": loads.l4_l5}}
            entry = dict(frame=record.frame) | result_part(record, result, self.model, loads.percent)
            self.store.entries.append(entry | ergonomics_part(ergo_l4))
        values = tuple(ergo[s.name].get(s.value) for s in self.valued)
        trunk = ergo["posture"].get("trunk_flexion")
        self.shown.append((record.frame, record.converged, values, trunk, loads.l4_l5.get("compression")))


class ResultKeys(Baker):
    """A Baker whose frames were solved elsewhere (the background run): :meth:`Baker.write` keys them as a bake
    does. Made from the solved joint values, not from the scene (so no scene reading, no solving here)."""

    def __init__(self, scene: bpy.types.Scene, arm: bpy.types.Object, records: list[FrameRecord],
                 thetas: np.ndarray) -> None:  # fmt: skip
        self.scene, self.arm, self.on_frame = scene, arm, None
        self.frames = [r.frame for r in records]
        self.model = model_of(arm)
        self.original = (scene.frame_current, scene.frame_subframe)
        self.thetas, self.records = thetas, records
        self.worlds = np.repeat(np.array(arm.matrix_world)[None], len(records), axis=0)
        self.failed = sum(not r.converged for r in records)
        self.shown, self.ergo = None, None


def read_frames(path: Path, arm: bpy.types.Object, report: FileReport | None) -> tuple[list, np.ndarray, list]:
    """(records, joint values (frames, n) in the manikin's joint order, the frames) of the result file ``path``."""
    model = model_of(arm)
    stream = ResultStream(path)
    records, thetas, frames = [], [], []
    for index, raw in stream.raw():
        f = stream.frame(index, raw)
        time_s = float(raw.get("time_s", 0.0))
        record = FrameRecord(f.number, bool(f.converged), int(raw.get("iterations", 0)), time_s, time_s,
                             list(f.unmet), list(raw.get("notes", [])),
                             {k: float(v) for k, v in raw.get("residuals", {}).items()})  # fmt: skip
        thetas.append([f.value(name) for name in model.joint_names])
        if report is not None:
            report.add_frame(record, f, raw)
            record.residuals = {}
        records.append(record)
        frames.append(f)
    return records, np.array(thetas, dtype=float), frames


def key_result(scene: bpy.types.Scene, arm: bpy.types.Object, path: Path) -> ResultKeys:
    """Key ``arm`` with the result file ``path`` (and store its ergonomics for the sidebar); the keyer, written."""
    body = arm.get(PRESET_KEY) or arm.get(FILE_KEY, "")
    report = FileReport(model_of(arm), body, None, plots=False, store=True)
    records, thetas, frames = read_frames(path, arm, report)
    keys = ResultKeys(scene, arm, records, thetas)
    arm.manikin.live = False  # the keyed action drives the pose from now on
    keys.write(ergo=report)
    keys.solved_frames = frames
    return keys


def object_origins(plan, frames: list[Frame], fps: float, start: int, origins: dict[str, np.ndarray]) -> dict:
    """Per object (by name) its origin (frames, 3) in the armature's space: where the plan rests it, or held,
    the solved holding hands' middle plus the plan's offset from them (the object where it lay, from the hands' grasp
    where their ways start in the first held segment). ``origins``: where each object is at the start."""
    out = {name: [] for name in origins}
    now = {name: np.asarray(o, dtype=float) for name, o in origins.items()}
    offsets: dict[str, np.ndarray] = {}
    segments = plan.segments
    for f in frames:
        t = (f.number - start) / fps
        segment = next((s for s in segments if t <= s.t1 + 1e-9), segments[-1])
        held = segment.carried
        for name in out:
            if held is not None and held[0] == name:
                hands = np.mean([f.tcp_position[tcp] for tcp in held[1]], axis=0)
                if name not in offsets:  # the plan's grasp: where the hands' ways start in the first held segment
                    ways = [segment.hands[tcp].points[0] for tcp in held[1] if tcp in segment.hands]
                    grip = np.mean(ways, axis=0) if len(ways) == len(held[1]) else hands
                    offsets[name] = now[name] - np.asarray(grip, dtype=float)
                now[name] = hands + offsets[name]
            else:
                offsets.pop(name, None)
                if name in segment.resting:
                    now[name] = np.asarray(segment.resting[name], dtype=float)
            out[name].append(now[name].copy())
    return {name: np.array(v) for name, v in out.items()}


def object_starts(scene: bpy.types.Scene, arm: bpy.types.Object, names) -> dict[str, tuple]:
    """Where each object named in ``names`` is now: (its box's centre in ``arm``'s space, its location)."""
    to_local = np.array(arm.matrix_world.inverted())
    found = {name: scene.objects.get(name) for name in names}
    return {name: (np.asarray(box_of(ob, to_local).center, dtype=float), np.array(ob.location))
            for name, ob in found.items() if ob is not None and ob.type == "MESH"}  # fmt: skip


def key_objects(scene: bpy.types.Scene, arm: bpy.types.Object, keys: ResultKeys, job, starts: dict) -> list[str]:
    """Key every object of the run where :func:`object_origins` has it (its location; linear, as the joints); the
    objects keyed. ``job``: the planned operations (``solver.operations.generate.Job``); ``starts``: where the
    objects were when the run started (:func:`object_starts`)."""
    found = {name: scene.objects.get(name) for name in starts}
    found = {name: ob for name, ob in found.items() if ob is not None}
    centres = {name: starts[name][0] for name in found}
    paths = object_origins(job.plan, keys.solved_frames, job.operate.fps, job.operate.start, centres)
    frames = np.array([f.number for f in keys.solved_frames], dtype=float)
    turn = np.array(arm.matrix_world.to_3x3().normalized())
    for name, ob in found.items():
        parent = np.eye(3) if ob.parent is None else np.array((ob.parent.matrix_world @ ob.matrix_parent_inverse)
                                                               .to_3x3())  # fmt: skip
        shifts = (paths[name] - centres[name]) @ turn.T @ np.linalg.inv(parent).T  # in the location's space
        locations = starts[name][1][None] + shifts
        for k in range(3):
            keyframes.replace_keys(keyframes.fcurve(ob, "location", k, GROUP), frames, locations[:, k])
    return list(found)
