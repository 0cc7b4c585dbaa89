"""bpy.ops.mbao.bake: "Bake Multi-Bounce AO". From a script (or with Blender in
the background) it bakes and returns; from the UI it bakes beside the UI, with
progress in the status bar, and Esc cancels."""

import time

import bpy

from . import jobs, results
from .scene_arrays import BakeInputError, bake_input
from .settings import bake_properties, bake_settings_of


def _mbao_settings(settings, bake):
    """What mbao is asked: mbao.bake's keyword arguments (SPEC 9)."""
    chosen = {name: settings[name] for name in ("bounces", "samples", "rho", "seed")}
    chosen.update(estimator=settings["estimator"].lower(), max_distance=settings["max_distance"] or None)
    if bake.image is not None:
        chosen.update(target="texture", resolution=list(bake.image.size), padding=settings["padding"])
    else:
        chosen["target"] = "vertices"
    return chosen


class MBAO_OT_bake(bpy.types.Operator):
    """Bake multi-bounce ambient occlusion of the selected mesh objects, the other visible objects occluding"""

    bl_idname = "mbao.bake"
    bl_label = "Bake Multi-Bounce AO"
    bl_options = {"REGISTER", "UNDO"}
    __annotations__ = bake_properties()

    def execute(self, context):
        if not self._start(context):
            return {"CANCELLED"}
        self._job.wait()
        return self._finish(context)

    def invoke(self, context, event):
        if not self._start(context):
            return {"CANCELLED"}
        manager = context.window_manager
        self._timer = manager.event_timer_add(0.1, window=context.window)
        manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC":
            self._job.cancel()
        if event.type != "TIMER":
            return {"PASS_THROUGH"}  # the rest of Blender stays in use
        if not self._job.done:
            context.workspace.status_text_set(f"mbao: baking, {self._job.fraction:.0%} (Esc cancels)")
            return {"RUNNING_MODAL"}
        context.window_manager.event_timer_remove(self._timer)
        context.workspace.status_text_set(None)
        return self._finish(context)

    def _start(self, context):
        """Starts the bake's job, or reports why it cannot start."""
        self._settings = settings = bake_settings_of(self)
        try:
            self._input = bake_input(context, settings)
            results.check_writable(self._input, settings, bpy.data.filepath)
            preferences = context.preferences.addons[__package__].preferences
            self._started = time.monotonic()
            self._job = jobs.BakeJob(self._input.arrays, _mbao_settings(settings, self._input), preferences.run_in)
        except (BakeInputError, ValueError, RuntimeError) as error:
            self.report({"ERROR"}, str(error))
            return False
        return True

    def _finish(self, context):
        job = self._job
        for message in job.warnings:
            self.report({"WARNING"}, f"mbao: {message}")
        if job.cancelled:
            self.report({"INFO"}, "mbao: bake cancelled; nothing was written")
            return {"CANCELLED"}
        if job.error is not None:
            self.report({"ERROR"}, f"mbao: {job.error}")
            return {"CANCELLED"}
        try:
            written = results.write(self._input, job.result, self._settings)
        except (RuntimeError, OSError) as error:  # an image Blender cannot save, say
            self.report({"ERROR"}, f"mbao: baked, but could not write the result: {error}")
            return {"CANCELLED"}
        self.report(
            {"INFO"},
            f"mbao: baked {written} in {time.monotonic() - self._started:.1f} s "
            f"({'in Blender' if job.run_in == 'BLENDER' else 'in a child process'})",
        )
        return {"FINISHED"}
