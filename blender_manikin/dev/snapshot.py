"""A picture of a posed manikin, rendered headless (Cycles on the CPU), from the built extension as a user has it:

    python -m blender_manikin.dev.snapshot [-o out/manikin.png] [--scenario presets/scenarios/box_lift.toml]
                                       [--size 640] [--samples 8]

builds the zip, installs it into a throwaway user directory, imports the scenario (default: the box lift) onto a
new manikin, solves it (with the installed copy's functions that Import Scenario and Solve Pose call) and renders
the body (the skinned human), the floor and the targets' places, denoised where Cycles has OpenImageDenoise. Run
from the repository root.
"""

from __future__ import annotations

import argparse
import atexit
import importlib
import os
import shutil
import sys
import tempfile
from pathlib import Path

from .build import ROOT, build, install, this_platform

DEFAULT_SCENARIO = ROOT / "presets" / "scenarios" / "box_lift.toml"


def _stage(bpy, size: int, samples: int, body_suffix: str, denoise: bool) -> None:
    """Floor, sun, camera (front-left, looking at the hips), Cycles on the CPU (denoised if ``denoise``)."""
    scene = bpy.context.scene
    for ob in list(scene.objects):
        if ob.type in {"MESH", "LIGHT", "CAMERA"} and not ob.name.endswith(body_suffix):
            bpy.data.objects.remove(ob, do_unlink=True)
    bpy.ops.mesh.primitive_plane_add(size=4.0)
    floor = bpy.context.active_object
    floor.data.materials.append(bpy.data.materials.new("floor"))
    floor.data.materials[0].diffuse_color = (0.35, 0.37, 0.4, 1.0)
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 3.0
    sun.rotation_euler = (0.7, 0.2, -0.6)
    scene.collection.objects.link(sun)
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    camera.location = (2.0, -2.7, 1.4)
    scene.collection.objects.link(camera)
    aim = camera.constraints.new("TRACK_TO")
    aim.target = bpy.data.objects.new("aim", None)
    aim.target.location = (0.0, -0.15, 0.8)
    scene.collection.objects.link(aim.target)
    scene.camera = camera
    scene.world = scene.world or bpy.data.worlds.new("world")
    background = scene.world.node_tree.nodes.get("Background") if scene.world.node_tree else None
    if background is not None:
        background.inputs["Color"].default_value = (0.75, 0.8, 0.85, 1.0)
    camera.data.lens = 60.0
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = denoise
    scene.cycles.denoising_prefilter = "FAST"  # the default also denoises the albedo and normals: twice the time
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"


def _materials(bpy, node_tree) -> None:
    """Principled materials from the viewport colors, so the render matches the viewport."""
    for material in bpy.data.materials:
        bsdf = node_tree(material).nodes.get("Principled BSDF")
        if bsdf is not None:
            bsdf.inputs["Base Color"].default_value = material.diffuse_color


def snapshot(output: Path, scenario: Path = DEFAULT_SCENARIO, size: int = 640, samples: int = 8) -> Path:
    """Render the solved scenario to ``output`` (PNG); returns its path. Imports bpy (a fresh process only)."""
    dist, user = tempfile.mkdtemp(prefix="manikin-dist-"), tempfile.mkdtemp(prefix="manikin-user-")
    for folder in (dist, user):  # about 450 MB a run (zips, installed wheels): left behind, they filled the disk
        atexit.register(shutil.rmtree, folder, ignore_errors=True)
    zip_path = build(Path(dist))[this_platform()]
    os.environ["BLENDER_USER_RESOURCES"] = user
    import bpy

    module = install(zip_path)
    compat = importlib.import_module(module + ".blender_manikin.scene.compat")  # the installed copy
    schema = importlib.import_module(module + ".blender_manikin.scene.schema")
    read = importlib.import_module(module + ".blender_manikin.scenario.read")
    solve = importlib.import_module(module + ".blender_manikin.pose.solve")
    _stage(bpy, size, samples, schema.BODY_SUFFIX, compat.denoiser_available())
    solve.solve_pose(read.import_scenario(bpy.context, scenario).arm)  # what Import Scenario and Solve Pose do
    _materials(bpy, compat.node_tree)
    output = output.resolve()
    output.parent.mkdir(parents=True, exist_ok=True)
    bpy.context.scene.render.filepath = str(output)
    bpy.ops.render.render(write_still=True)
    return output


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m blender_manikin.dev.snapshot", description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, default=ROOT / "out" / "manikin.png")
    parser.add_argument("--scenario", type=Path, default=DEFAULT_SCENARIO)
    parser.add_argument("--size", type=int, default=640, help="image width and height, pixels")
    parser.add_argument("--samples", type=int, default=8, help="Cycles samples per pixel (denoised)")
    args = parser.parse_args(argv)
    print(snapshot(args.output, args.scenario, args.size, args.samples))
    return 0


if __name__ == "__main__":
    sys.exit(main())
