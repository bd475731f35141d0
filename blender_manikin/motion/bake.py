"""Baking a motion (bpy): the animated targets solved frame by frame, the joint values keyed in bulk.

For each frame the scene is set to it (so keyed, constrained or parented target empties are where the user
animated them), the scene is read into a solver problem exactly as Solve Pose reads it, and
:func:`solver.motion.frames.solve_frames` solves it warm-started from the previous frame within the per-frame change
bound (a frame that would need a jump does not converge and its notes say which target moved too far). The
solutions are buffered; :meth:`Baker.write` keys every joint's bone channel (and a carried box) at once, so a
cancelled bake leaves the scene as it was. :class:`Baker` works in steps so a modal operator can show progress
and listen for Esc; the batch script streams each solved frame into its files (``on_frame``) and, after a Ctrl-C,
keys the frames solved.

Each frame is read from the scene, even after a scenario import whose Problem could give the frame's targets
directly: the scene is the truth (the user may have moved, re-keyed, parented or constrained an empty, moved an
obstacle or changed a setting since), and Blender blends keyed rotations linearly (normalised) where the scenario
slerps, so only the scene's empties are what the user sees. A frame's read shares the previous frame's constraints
(``read_problem``'s ``reuse``), and what cannot change with the frame is read once per bake (``problem_io.Held``:
the model, the objects to read, meshes nothing animates): about 0.3 ms against a solve of about 1.
"""

from __future__ import annotations

import json
import time
import zlib
from collections.abc import Callable, Iterator
from dataclasses import asdict, dataclass, field
from typing import Protocol

import bpy
import numpy as np

from ...solver import ManikinError, Problem, Result
from ...solver.body.spatial import matrix_to_quat
from ...solver.io.result.write import interrupts_held
from ...solver.motion.frames import MotionLimits, solve_frames
from ..scene import carried_object, keyframes, problem_io
from ..scene.armature import layout_of, model_of, read_x, write_pose
from ..scene.schema import BAKE_KEY, FRAMES_KEY, RESULT_KEY


class Ergonomics(Protocol):
    """What a bake hands each solved frame for the sidebar (:class:`.report.MotionReport` with a frame store)."""

    store: object | None  # a .frame_store.FrameStore (not imported: that module's annotations name this one's)

    def add(self, record: FrameRecord, result: Result) -> None: ...

    def motion(self) -> dict[str, dict]: ...


@dataclass(slots=True)
class FrameRecord:
    """How one frame went: solver time, and wall time including reading the scene. The residuals are there while
    the frame is handed on (:meth:`Baker.step`: the sidebar's entry, ``on_frame``'s files) and dropped after it: a
    long bake keeps a few numbers per frame (slots: no dict per record either)."""

    frame: int
    converged: bool
    iterations: int
    time_s: float
    wall_s: float
    unmet: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    residuals: dict[str, float] = field(default_factory=dict)

    def why(self) -> str:
        """Why a frame did not converge, one line starting with its number: "frame 12: out of reach: hand_r"."""
        notes = [note.removeprefix(f"frame {self.frame}: ") for note in self.notes]
        detail = "; ".join(notes) or ("out of reach: " + ", ".join(self.unmet) if self.unmet else "not converged")
        return f"frame {self.frame}: {detail}"


def limits_of(arm: bpy.types.Object) -> MotionLimits | None:
    """The manikin's per-frame change bound (None when switched off)."""
    s = arm.manikin
    return MotionLimits(s.max_joint_change, s.max_root_shift) if s.bound_motion else None


class Baker:
    """Solves ``frame_start..frame_end`` for ``arm`` in steps, then writes the keys (or cancels: nothing written).

    ``on_frame(record, result)`` is called for each solved frame (to stream it into files and reports: the
    Results themselves are not kept); a frame's bookkeeping and that call finish before a Ctrl-C takes effect.
    """

    box_tcps: tuple[str, str] | None = None  # a carried box's TCPs (a subclass keying frames solved elsewhere: none)
    hands: np.ndarray | None = None  # their solved positions per frame (frames, 2, 3), m: the box is keyed from them

    def __init__(
        self,
        scene: bpy.types.Scene,
        arm: bpy.types.Object,
        frame_start: int,
        frame_end: int,
        on_frame: Callable[[FrameRecord, Result], None] | None = None,
    ) -> None:
        if frame_end < frame_start:
            raise ManikinError(f"frame range {frame_start}..{frame_end} is empty (end before start)")
        self.scene, self.arm, self.on_frame = scene, arm, on_frame
        self.frames = list(range(frame_start, frame_end + 1))
        self.model = model_of(arm)
        self.original = (scene.frame_current, scene.frame_subframe)
        self.original_x = read_x(arm)
        scene.frame_set(frame_start)
        try:  # what cannot change with the frame is read once, for this bake only
            self.held = problem_io.Held(arm)
            first = problem_io.read_problem(arm, held=self.held)  # raises ManikinError naming the empty at fault
        except ManikinError:
            scene.frame_set(self.original[0], subframe=self.original[1])
            raise
        self.n_x = first.problem.n_x
        self._first: Problem | None = first.problem
        self._read = first  # the scene's problem last read: the next frame's shares its parts when it can
        self.thetas = np.zeros((len(self.frames), self.model.n))
        self.worlds = np.zeros((len(self.frames), 4, 4))  # the armature object's world matrix at each frame
        self.box_tcps = carried_object.keyed_tcps(arm)  # a carried box's TCPs: their solved positions are kept
        self.hands = None if self.box_tcps is None else np.zeros((len(self.frames), 2, 3))
        self.records: list[FrameRecord] = []
        self.failed = 0  # frames that did not converge
        self.shown: Result | None = None  # the result at the frame the scene returns to, if baked (sidebar)
        self.last_x = first.x0  # the latest solution (joints, forces), to show progress
        self.ergo: Ergonomics | None = None  # evaluates each frame's ergonomics for the sidebar, if set
        self._solving: Iterator[tuple[int, Result]] = solve_frames(
            self._problem_at, self.frames, first.x0, first.options, limits_of(arm)
        )

    @property
    def done(self) -> int:
        return len(self.records)

    @property
    def finished(self) -> bool:
        return self.done == len(self.frames)

    def _problem_at(self, frame: int) -> Problem:
        if self._first is not None:  # the first frame was read (and the scene set) in __init__
            problem, self._first = self._first, None
            return problem
        self.scene.frame_set(frame)
        self._read = problem_io.read_problem(self.arm, start=False, reuse=self._read, held=self.held)
        problem = self._read.problem
        if problem.n_x != self.n_x:
            raise ManikinError(f"frame {frame}: the supports changed during the range; bake the parts separately")
        return problem

    def step(self, budget_s: float = 0.0) -> bool:
        """Solve frames for about ``budget_s`` seconds (at least one); True when every frame is solved."""
        t_end = time.perf_counter() + budget_s
        while not self.finished:
            t0 = time.perf_counter()
            frame, result = next(self._solving)
            record = FrameRecord(
                frame,
                bool(result.converged),
                int(result.iterations),
                float(result.time_s),
                time.perf_counter() - t0,
                list(result.unmet),
                list(result.notes),
                {k: float(v) for k, v in result.residuals.items()},
            )
            with interrupts_held():  # the frame is in every output or in none
                self.thetas[self.done] = result.theta
                self.worlds[self.done] = np.array(self.arm.matrix_world)  # the scene is at ``frame``
                if self.hands is not None:  # the solve's kinematics (kept with the result): no forward when keying
                    self.hands[self.done] = carried_object.tcp_points(self.model, self.box_tcps, result.state.kin)
                self.records.append(record)
                self.failed += not record.converged
                if self.ergo is not None:
                    self.ergo.add(record, result)
                if self.on_frame is not None:
                    self.on_frame(record, result)
                record.residuals = {}  # in every output now; kept, they were most of a frame's memory (2 kB)
            if frame == self.original[0]:
                self.shown = result
            self.last_x = result.x
            if time.perf_counter() >= t_end:
                break
        return self.finished

    def show_progress(self) -> None:
        """Pose the manikin with the latest solved frame (the keys are written at the end)."""
        write_pose(self.arm, self.last_x)

    def run(self) -> None:
        """Solve every remaining frame."""
        while not self.step(1.0):
            pass

    def not_converged(self) -> list[int]:
        return [r.frame for r in self.records if not r.converged]

    def write(self, thin: bool = False, ergo: Ergonomics | None = None, release: bool = False) -> float:
        """Key every joint of the solved frames (one F-curve per bone channel, grouped by bone) and the carried box
        between the hands (:func:`..scene.carried_object.key_carried`), store the report on the armature and return the
        scene to its frame. Returns the seconds spent keying. ``thin``: a joint is keyed where it changes (inner
        keys of runs of equal values left out: the same curves, for long motions far fewer keys, each held twice in
        memory once the scene is evaluated). ``ergo``: the report whose frame store the sidebar reads (default: the
        one in ``ergo``). ``release``: drop the joint values once keyed (~1.4 kB a frame; a headless job that draws no
        picture from them), before the keyed scene is evaluated."""
        t0 = time.perf_counter()
        arm, layout = self.arm, layout_of(self.model)
        frames = np.array([r.frame for r in self.records], dtype=float)
        thetas = self.thetas[: len(frames)]
        quats = self._quaternion_bones(thetas)
        for b, bone in enumerate(layout.bones):
            base = f'pose.bones["{bpy.utils.escape_identifier(bone.name)}"]'
            for c in bone.channels:
                fc = keyframes.fcurve(arm, f"{base}.{c.prop}", c.index, bone.name)
                keyframes.replace_keys(fc, frames, c.sign * thetas[:, c.joint], thin)
            if b in quats:
                for k in range(4):
                    fc = keyframes.fcurve(arm, f"{base}.rotation_quaternion", k, bone.name)
                    keyframes.replace_keys(fc, frames, quats[b][:, k], thin)
        hands = None if self.hands is None else self.hands[: len(frames)]
        carried_object.key_carried(arm, frames, thetas, self.worlds[: len(frames)], thin, hands)  # box follows hands
        if release:
            del thetas
            self.thetas = self.thetas[:0].copy()
        seconds = time.perf_counter() - t0
        arm[BAKE_KEY] = json.dumps(self.summary())
        self.scene.frame_set(self.original[0], subframe=self.original[1])
        if self.shown is not None:  # the pose there is the keyed one; the sidebar shows its result
            problem_io.write_result(arm, self.shown)
        self._store(ergo or self.ergo, thin)
        return seconds

    def _store(self, ergo: Ergonomics | None, thin: bool) -> None:
        """Each frame's sidebar entry on the armature (``FRAMES_KEY``: a group of JSON texts, "head" and one per
        frame) and each graphed score keyed as a custom property of its data (the Graph Editor's curves)."""
        arm = self.arm
        store = ergo.store if ergo is not None else None
        if store is None or not store.entries:
            if FRAMES_KEY in arm:  # the stored frames are of an earlier bake: the sidebar must not show them
                del arm[FRAMES_KEY]
            return
        crc = zlib.crc32(str(arm.get(RESULT_KEY, "")).encode())
        arm[FRAMES_KEY] = {"head": json.dumps(store.head(ergo.motion(), crc), allow_nan=False)} | store.texts()
        for prop, (frames, values) in store.series().items():
            arm.data[prop] = float(values[0])
            fc = keyframes.fcurve(arm.data, f'["{prop}"]', 0, "Manikin ergonomics")
            keyframes.replace_keys(fc, frames, values, thin)

    def _quaternion_bones(self, thetas: np.ndarray) -> dict[int, np.ndarray]:
        """(frames, 4) quaternions of the bones whose joints are not one Euler channel each (body files only)."""
        layout = layout_of(self.model)
        inexact = [b for b, bone in enumerate(layout.bones) if not bone.exact]
        out = {b: np.zeros((len(thetas), 4)) for b in inexact}
        for f, theta in enumerate(thetas if inexact else ()):
            basis = layout.basis_matrices(self.model.forward(theta))
            for b in inexact:
                out[b][f] = matrix_to_quat(basis[b][:3, :3])
        return out

    def summary(self) -> dict:
        """What the sidebar and scripts read back from ``arm["manikin_bake"]``."""
        failed = [asdict(r) for r in self.records if not r.converged]
        for r in failed:
            r.pop("residuals")
        return dict(
            frame_start=self.frames[0],
            frame_end=self.frames[-1],
            solved=self.done,
            not_converged=failed,
            solve_s=sum(r.wall_s for r in self.records),
        )

    def cancel(self) -> None:
        """Leave everything as it was before the bake (nothing has been keyed yet)."""
        self.scene.frame_set(self.original[0], subframe=self.original[1])
        write_pose(self.arm, self.original_x)
