"""Live mode: moving a target, loop or load empty re-solves its manikin (when the manikin's Live is on); moving
or reshaping an obstacle re-solves every manikin in live mode.

The ``depsgraph_update_post`` handler only notes which manikins have a moved empty (or, for an obstacle whose
transform or geometry changed, every live manikin) and arms a timer; the timer solves at most once per
``INTERVAL`` (however many updates a drag produces), warm-started from the current pose with the manikin's live
iteration limit, and puts a carried box between the solved hands. Writing the pose (and moving the box) triggers
further depsgraph updates; two things keep that from looping: a re-entrancy guard while the timer writes, and each
manikin's last solved inputs (target frames, loop offsets, forces, obstacles, settings) - a re-solve happens only
when the inputs differ, which a pose write never causes (loop and load empties ride on the TCPs, but their offsets
stay the same; the body and the carried box are no scene obstacles: the box's rows follow the hands).

While dragging, a live solve writes its result without the ergonomics scores (RULA, REBA, OWAS, ...: about a fifth of
a live re-solve's time, docs/BENCHMARKS.md "Live drag"); the Result panel says they follow, and a second timer adds
them once no live solve has happened for ``SETTLE`` (the drag has ended), from the last result kept here.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

import bpy
from bpy.app.handlers import persistent

from ...solver.errors import ManikinError
from ..scene.schema import ERROR_KEY, is_manikin, is_obstacle, rig_of

if TYPE_CHECKING:
    from ...solver.iteration.result import Result
    from ..scene.problem_io import Inputs  # imports the solver: only for the type checker

classes: tuple[type, ...] = ()  # nothing registered as a class: a depsgraph handler and a timer

INTERVAL = 1.0 / 30.0  # s, at most one solve per manikin per interval
SETTLE = 0.3  # s without a live solve after which a drag counts as ended and the scores are added

_busy = False  # re-entrancy guard: True while the timer solves and writes
_pending: set[str] = set()  # names of manikin armatures with moved empties
_last_inputs: dict[str, Inputs] = {}  # armature name -> the inputs last solved
_unscored: dict[str, Result] = {}  # armature name -> its last live result, written without the scores
_last_solve = 0.0  # time.monotonic() of the last live solve


def _live_rig(obj: bpy.types.Object) -> bpy.types.Object | None:
    rig = rig_of(obj)
    return rig if rig is not None and rig.manikin.live else None


def request(arm: bpy.types.Object) -> None:
    """Ask for a re-solve of ``arm`` (e.g. when Live is switched on)."""
    _pending.add(arm.name)
    _last_inputs.pop(arm.name, None)
    if not bpy.app.timers.is_registered(solve_pending):
        bpy.app.timers.register(solve_pending, first_interval=INTERVAL)


@persistent
def on_depsgraph_update(scene: bpy.types.Scene, depsgraph: bpy.types.Depsgraph) -> None:
    """Note manikins whose empties (or settings) changed, or every live manikin when an obstacle moved or was
    reshaped; arm the timer. Never writes data itself."""
    if _busy:
        return
    obstacle_changed = False
    for update in depsgraph.updates:
        obj = update.id.original if isinstance(update.id, bpy.types.Object) else None
        if obj is None:
            continue
        rig = _live_rig(obj)
        if rig is not None:  # our own pose writes land here too; the input signature filters them out
            _pending.add(rig.name)
        elif not obstacle_changed and (update.is_updated_transform or update.is_updated_geometry):
            obstacle_changed = is_obstacle(obj)  # a mesh edit updates its object's geometry too
    if obstacle_changed:
        _pending.update(ob.name for ob in scene.objects if is_manikin(ob) and ob.manikin.live)
    if _pending and not bpy.app.timers.is_registered(solve_pending):
        bpy.app.timers.register(solve_pending, first_interval=INTERVAL)


def solve_pending() -> None:
    """Timer: re-solve every noted manikin whose inputs changed since its last solve."""
    global _busy
    names = sorted(_pending)
    _pending.clear()
    _busy = True
    try:
        for name in names:
            arm = bpy.data.objects.get(name)
            if arm is None or not is_manikin(arm) or not arm.manikin.live:
                continue
            _solve(arm)
    finally:
        _busy = False
    return None


def _solve(arm: bpy.types.Object) -> None:
    from ...solver import solve
    from ..scene import problem_io

    try:
        sp = problem_io.read_problem(arm, live=True)
        if sp.inputs.same_as(_last_inputs.get(arm.name)):
            return
        _last_inputs[arm.name] = sp.inputs
        result = solve(sp.problem, sp.x0, sp.options)
        problem_io.write_result(arm, result, scores=False)  # the scores follow when the drag ends
        _defer_scores(arm.name, result)
    except ManikinError as exc:
        if arm.get(ERROR_KEY) != str(exc):  # shown in the sidebar; written once, not on every update
            arm[ERROR_KEY] = str(exc)


def _defer_scores(name: str, result: Result) -> None:
    """Keep ``result`` for :func:`score_settled` and (re)arm its timer."""
    global _last_solve
    _unscored[name] = result
    _last_solve = time.monotonic()
    if not bpy.app.timers.is_registered(score_settled):
        bpy.app.timers.register(score_settled, first_interval=SETTLE)


def score_settled(force: bool = False) -> float | None:
    """Timer: once no live solve has happened for ``SETTLE`` (or ``force``), add the ergonomics scores to every
    result written without them; until then, wait the rest of ``SETTLE``."""
    global _busy
    wait = SETTLE - (time.monotonic() - _last_solve)
    if wait > 0.0 and not force:
        return wait
    from ..scene import problem_io

    results = dict(_unscored)
    _unscored.clear()
    _busy = True  # the result property's write triggers an update: nothing to re-solve
    try:
        for name, result in results.items():
            arm = bpy.data.objects.get(name)
            if arm is not None and is_manikin(arm):
                problem_io.write_scores(arm, result)
    finally:
        _busy = False
    return None


def register() -> None:
    if on_depsgraph_update not in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.append(on_depsgraph_update)


def unregister() -> None:
    while on_depsgraph_update in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.remove(on_depsgraph_update)
    for timer in (solve_pending, score_settled):
        if bpy.app.timers.is_registered(timer):
            bpy.app.timers.unregister(timer)
    _pending.clear()
    _last_inputs.clear()
    _unscored.clear()
