"""The Bake Motion operator: solve a frame range and key the manikin, with progress, Esc to cancel, and undo.

Invoked from the UI it runs modally on a timer, solving frames in small time slices so the status bar and the
progress cursor update and Esc stops it (nothing is keyed then). Run from a script, in background mode or
with ``EXEC_DEFAULT`` it bakes in one go. Either way frames that did not converge are reported and stored on the
armature (``arm["manikin_bake"]``).
"""

from __future__ import annotations

import bpy
from bpy.props import IntProperty

from ...solver.errors import ManikinError
from ..scene.schema import FILE_KEY, PRESET_KEY, rig_of

SLICE_S = 0.05  # s of solving per timer tick: keeps the UI responsive to Esc
VIEW_EVENTS = {"MIDDLEMOUSE", "WHEELUPMOUSE", "WHEELDOWNMOUSE", "TRACKPADPAN", "TRACKPADZOOM", "MOUSEMOVE"}
SHOWN_FAILURES = 8  # frames listed in the report line


class MANIKIN_OT_bake_motion(bpy.types.Operator):
    """Solve every frame of a range for the animated targets (warm-started, without jumps) and key the manikin"""

    bl_idname = "manikin.bake_motion"
    bl_label = "Bake Motion"
    bl_options = {"REGISTER", "UNDO"}

    # SKIP_SAVE: a range typed once must not replace the scene's range in every later click of Bake Motion
    frame_start: IntProperty(name="Start", description="First frame (default: the scene's start)",
                             options={"SKIP_SAVE"})  # fmt: skip
    frame_end: IntProperty(name="End", description="Last frame (default: the scene's end)", options={"SKIP_SAVE"})

    baker = None  # the running Baker (not an annotation: Blender reads an operator's annotations as properties)
    timer = None

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        if rig_of(context.active_object) is None:
            cls.poll_message_set("Select a manikin, or one of its targets")
            return False
        return context.mode in {"OBJECT", "POSE"}

    def start(self, context: bpy.types.Context) -> bool:
        """Set up the Baker for the chosen range (default: the scene's); False after reporting why not."""
        from .bake import Baker
        from .frame_store import STORE_MAX
        from .report import MotionReport

        scene = context.scene
        for name, default in (("frame_start", scene.frame_start), ("frame_end", scene.frame_end)):
            if not self.properties.is_property_set(name):
                setattr(self, name, default)
        arm = rig_of(context.active_object)
        if arm.manikin.live:  # the baked action drives the pose from now on
            arm.manikin.live = False
            self.report({"INFO"}, "Live switched off for the bake")
        try:
            self.baker = Baker(scene, arm, self.frame_start, self.frame_end)
        except ManikinError as exc:
            self.report({"ERROR"}, str(exc))
            return False
        if len(self.baker.frames) <= STORE_MAX:  # each frame's ergonomics for the sidebar (motion/ergonomics_panel.py)
            body = arm.get(PRESET_KEY) or arm.get(FILE_KEY, "")
            self.baker.ergo = MotionReport(self.baker.model, body, None, plots=False, store=True)
        context.window_manager.progress_begin(0, len(self.baker.frames))
        return True

    def execute(self, context: bpy.types.Context) -> set[str]:
        if not self.start(context):
            return {"CANCELLED"}
        try:
            while not self.baker.step(SLICE_S):
                context.window_manager.progress_update(self.baker.done)
        except ManikinError as exc:
            return self.stop(context, str(exc))
        return self.finish(context)

    def invoke(self, context: bpy.types.Context, event: bpy.types.Event) -> set[str]:
        if bpy.app.background or context.window is None:
            return self.execute(context)
        if not self.start(context):
            return {"CANCELLED"}
        wm = context.window_manager
        self.timer = wm.event_timer_add(0.001, window=context.window)
        wm.modal_handler_add(self)
        self.show_status(context)
        return {"RUNNING_MODAL"}

    def modal(self, context: bpy.types.Context, event: bpy.types.Event) -> set[str]:
        if event.type == "ESC":
            return self.stop(context, f"Bake cancelled at frame {self.current_frame()}; nothing keyed")
        if event.type in VIEW_EVENTS:
            return {"PASS_THROUGH"}  # the view may turn and zoom while the bake runs
        if event.type != "TIMER":
            return {"RUNNING_MODAL"}  # but the scene must not change under it
        try:
            finished = self.baker.step(SLICE_S)
        except ManikinError as exc:
            return self.stop(context, str(exc))
        context.window_manager.progress_update(self.baker.done)
        if finished:
            return self.finish(context)
        self.baker.show_progress()  # the manikin follows the bake on screen
        self.show_status(context)
        return {"RUNNING_MODAL"}

    def current_frame(self) -> int:
        """The frame being solved (the last solved one)."""
        baker = self.baker
        return baker.records[-1].frame if baker.records else baker.frames[0]

    def show_status(self, context: bpy.types.Context) -> None:
        """The progress line in the status bar."""
        baker = self.baker
        if context.workspace is not None:
            failed = len(baker.not_converged())
            note = f", {failed} not converged" if failed else ""
            context.workspace.status_text_set(
                f"Baking motion: frame {self.current_frame()} ({baker.done}/{len(baker.frames)}{note}). Esc to cancel"
            )

    def cleanup(self, context: bpy.types.Context) -> None:
        """Remove the timer, the progress cursor and the status line."""
        wm = context.window_manager
        if self.timer is not None:
            wm.event_timer_remove(self.timer)
            self.timer = None
        wm.progress_end()
        if context.workspace is not None:
            context.workspace.status_text_set(None)

    def stop(self, context: bpy.types.Context, message: str) -> set[str]:
        """Cancel the bake (nothing keyed) and report ``message``."""
        self.baker.cancel()
        self.cleanup(context)
        self.report({"WARNING"} if message.startswith("Bake cancelled") else {"ERROR"}, message)
        return {"CANCELLED"}

    def finish(self, context: bpy.types.Context) -> set[str]:
        """Key the solved frames and report the frames that did not converge."""
        baker = self.baker
        try:
            baker.write()
        except ManikinError as exc:
            return self.stop(context, f"Solved {baker.done} frames but could not key them: {exc}")
        self.cleanup(context)
        failed = baker.not_converged()
        n = len(baker.frames)
        if not failed:
            self.report({"INFO"}, f"Baked {n} frames ({baker.frames[0]}-{baker.frames[-1]}), all converged")
            return {"FINISHED"}
        shown = ", ".join(map(str, failed[:SHOWN_FAILURES])) + (", ..." if len(failed) > SHOWN_FAILURES else "")
        self.report({"WARNING"}, f"Baked {n} frames; {len(failed)} did not converge: {shown}")
        for record in [r for r in baker.records if not r.converged][:SHOWN_FAILURES]:
            self.report({"WARNING"}, record.why())  # "frame 12: out of reach: hand_r", "frame 13: a target moved ..."
        return {"FINISHED"}


classes = (MANIKIN_OT_bake_motion,)
