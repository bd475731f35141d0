"""A manikin's life in a Blender session, run by tests/blender/test_lifecycle.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/lifecycle_session.py <zip> <out.json> <work dir>

Add Manikin from a body file, then from a preset (and once the file moved); Add Load with a negative mass; the
shipped box lift imported and its armature, box, a target and an obstacle renamed, then solved and exported;
Duplicate Manikin and Delete Manikin (a user's object parented to the copy stays); scenarios imported one after
another (replacing and keeping the previous one's obstacles and box) and into a second scene; the armature deleted
with X, Solve asked for on its leftovers, and Delete Manikin clearing them. Each part records what it saw (or the
error it met) in the JSON; bpy is imported here only.
"""

from __future__ import annotations

import importlib
import json
import shutil
import sys
import time
import traceback
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from session_tools import Layout, error_of, install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
SCENARIOS = ROOT / "presets" / "scenarios"
seen: dict = {"crashed": {}}
started = time.perf_counter()

import bpy  # noqa: E402

module = install(ZIP)
carried_object = importlib.import_module(module + ".blender_manikin.scene.carried_object")


def part(name: str):
    """Run a part of the session; a crash is recorded (a part about a missing feature fails its test only)."""

    def run(fn):
        try:
            fn()
        except Exception:  # noqa: BLE001  (recorded for the test to show)
            seen["crashed"][name] = traceback.format_exc()[-1500:]
        return fn

    return run


def activate(ob: bpy.types.Object) -> None:
    for other in bpy.context.view_layer.objects.selected:
        other.select_set(False)
    ob.select_set(True)
    bpy.context.view_layer.objects.active = ob


def imported(scene: bpy.types.Scene) -> list[str]:
    return sorted(ob.name for ob in scene.objects if "manikin_imported" in ob)


def boxes() -> list[str]:
    return sorted(ob.name for ob in bpy.data.objects if "manikin_carried" in ob)


def owned(arm: bpy.types.Object) -> list[str]:
    """The names of ``arm``'s body objects, TCP empties and targets (by pointer), for counting."""
    found = [c.name for c in arm.children if "manikin_display" in c or "manikin_tcp" in c]
    found += [ob.name for ob in bpy.data.objects if ob.manikin_target.role != "NONE" and ob.manikin_target.rig == arm]
    return sorted(found)


def owned_objects(arm: bpy.types.Object) -> list[bpy.types.Object]:
    return [bpy.data.objects[name] for name in owned(arm)]


def remembered() -> list[str]:
    """The file paths and one-shot choices of our operators that a click would reuse from the last call (a script's
    call never does: Blender fills in the last properties for buttons only, except those marked SKIP_SAVE)."""
    found = []
    for name in dir(bpy.ops.manikin):
        rna = getattr(bpy.ops.manikin, name).get_rna_type()
        for prop in rna.properties:
            one_shot = prop.identifier in ("frame_start", "frame_end", "target")
            if (one_shot or getattr(prop, "subtype", "") in ("FILE_PATH", "DIR_PATH")) and not prop.is_skip_save:
                found.append(f"{name}.{prop.identifier}")
    return sorted(found)


@part("body_file")
def _body_file() -> None:
    """Item 1: a body file given once is not used by the next Add Manikin (and its move breaks nothing)."""
    body = WORK / "tall.toml"
    shutil.copy(ROOT / "presets" / "manikins" / "male_95.toml", body)
    bpy.ops.manikin.add_manikin(filepath=str(body))
    first = bpy.context.active_object
    bpy.ops.manikin.add_manikin(preset="female_5")
    second = bpy.context.active_object
    body.rename(WORK / "moved.toml")
    error = error_of(lambda: bpy.ops.manikin.add_manikin(preset="male_50"))
    third = bpy.context.active_object
    seen["body_file"] = dict(
        first=[first["manikin_preset"], first["manikin_body_file"]],
        second=[second["manikin_preset"], second["manikin_body_file"]],
        moved_error=error,
        third=[third["manikin_preset"], third["manikin_body_file"]],
        remembered=remembered(),
    )


@part("load")
def _load() -> None:
    """Item 5: Add Load with -3 kg is refused in one line; 4 kg is added."""
    arm = bpy.context.active_object
    error = error_of(lambda: bpy.ops.manikin.add_load(tcp="hand_l", mass=-3.0))
    made_negative = "load.hand_l" in bpy.data.objects
    activate(arm)
    bpy.ops.manikin.add_load(tcp="hand_r", mass=4.0)
    seen["load"] = dict(
        error=error, made_negative=made_negative, force=list(bpy.data.objects["load.hand_r"].manikin_target.force)
    )


for ob in list(bpy.data.objects):  # a clean scene for the rest
    bpy.data.objects.remove(ob, do_unlink=True)
scene1 = bpy.context.scene


def midpoint(arm: bpy.types.Object) -> list[float]:
    a, b = (
        next(c for c in arm.children if c.get("manikin_tcp") == t).matrix_world.translation
        for t in ("hand_r", "hand_l")
    )
    return list((a + b) / 2.0)


@part("rename")
def _rename() -> None:
    """Item 2: renaming the armature, the box, a target and an obstacle changes nothing but the names."""
    bpy.ops.manikin.import_scenario(filepath=str(SCENARIOS / "box_lift_motion.toml"))
    arm = bpy.context.active_object
    box = carried_object.find_carried(arm)
    arm.name, box.name = "worker", "crate"
    bpy.data.objects["target.hand_r"].name = "right hand goal"
    bpy.data.objects["shelf"].name = "rack"
    bpy.context.scene.frame_set(30)
    activate(arm)
    before = list(box.matrix_world.translation)
    solved = sorted(bpy.ops.manikin.solve_pose())
    bpy.context.view_layer.update()
    bpy.ops.manikin.export_scenario(filepath=str(WORK / "renamed.toml"))
    text = (WORK / "renamed.toml").read_text(encoding="utf-8")
    seen["rename"] = dict(
        solved=solved,
        box_before=before,
        box_after=list(box.matrix_world.translation),
        hands=midpoint(arm),
        found=getattr(carried_object.find_carried(arm), "name", None),
        carried_in_export="[carried]" in text,
        rack_in_export='name = "rack"' in text,
        targets=len([ob for ob in bpy.data.objects if ob.manikin_target.rig == arm]),
    )


@part("duplicate")
def _duplicate() -> None:
    """Item 4: Duplicate Manikin gives a working manikin of its own beside the first."""
    arm = bpy.data.objects["worker"]
    activate(arm)
    before = owned(arm)
    done = sorted(bpy.ops.manikin.duplicate_manikin())
    copy = bpy.context.active_object
    hand, hand_copy = (next(ob for ob in owned_objects(a) if ob.manikin_target.tcp == "hand_r"
                            and ob.manikin_target.role == "TARGET") for a in (arm, copy))  # fmt: skip
    bpy.context.scene.frame_set(20)
    keyed = [list(hand.matrix_world.translation), list(hand_copy.matrix_world.translation)]
    drivers = {v.targets[0].id.name for fc in copy.animation_data.drivers for v in fc.driver.variables}
    box_copy = carried_object.find_carried(copy)
    activate(copy)
    solved = sorted(bpy.ops.manikin.solve_pose())
    result = json.loads(copy["manikin_result"])
    seen["duplicate"] = dict(
        done=done,
        name=copy.name,
        is_new=copy != arm,
        before=len(before),
        after=len(owned(arm)),
        copy=len(owned(copy)),
        bodies=sorted(c["manikin_display"] for c in copy.children if "manikin_display" in c),
        tcps=len([c for c in copy.children if "manikin_tcp" in c]),
        tcps_first=len([c for c in arm.children if "manikin_tcp" in c]),
        offset=list(copy.matrix_world.translation - arm.matrix_world.translation),
        keyed=keyed,
        drivers=sorted(drivers),
        box=None if box_copy is None else box_copy.name,
        box_first=carried_object.find_carried(arm).name,
        solved=solved,
        converged=result["converged"],
        frames=[bpy.context.scene.frame_start, bpy.context.scene.frame_end],
    )


@part("delete")
def _delete() -> None:
    """Item 4: Delete Manikin removes the copy and all that is its, nothing else; a user's tool on its hand stays."""
    arm, copy = bpy.data.objects["worker"], bpy.data.objects["worker.001"]
    total = len(bpy.data.objects)
    first = owned(arm)
    bpy.ops.mesh.primitive_cube_add(size=0.05)
    tool = bpy.context.active_object
    tool.name = "wrench"
    tool.parent = next(c for c in copy.children if c.get("manikin_tcp") == "hand_r")
    bpy.context.view_layer.update()
    where = list(tool.matrix_world.translation)
    copy_box = carried_object.find_carried(copy).name
    copy_owned = owned(copy)
    activate(copy)
    done = sorted(bpy.ops.manikin.delete_manikin())
    bpy.context.view_layer.update()
    seen["delete"] = dict(
        done=done,
        removed=total + 1 - len(bpy.data.objects),
        copy_gone="worker.001" not in bpy.data.objects,
        left=[name for name in copy_owned if name in bpy.data.objects],
        box_gone=copy_box not in bpy.data.objects,
        first_same=owned(arm) == first,
        first_box=carried_object.find_carried(arm) is not None,
        tool=tool.name in bpy.data.objects,
        tool_where=[where, list(tool.matrix_world.translation)],
        armatures=len(bpy.data.armatures),
    )
    bpy.data.objects.remove(tool, do_unlink=True)


@part("replace")
def _replace() -> None:
    """Item 3: a second scenario replaces the first one's obstacles and box (the option's default), or keeps them."""
    arm = bpy.data.objects["worker"]
    activate(arm)
    first = imported(scene1)
    bpy.ops.manikin.import_scenario(filepath=str(SCENARIOS / "cabinet_reach.toml"))
    after_cabinet = dict(obstacles=imported(scene1), boxes=boxes())
    activate(arm)
    bpy.ops.manikin.import_scenario(filepath=str(SCENARIOS / "cabinet_reach.toml"))
    again = imported(scene1)
    activate(arm)
    bpy.ops.manikin.import_scenario(filepath=str(SCENARIOS / "deep_squat.toml"))
    squat = imported(scene1)
    activate(arm)
    solved = sorted(bpy.ops.manikin.solve_pose())
    result = json.loads(arm["manikin_result"])
    seen["replace"] = dict(
        first=first,
        after_cabinet=after_cabinet,
        again=again,
        squat=squat,
        solved=solved,
        converged=result["converged"],
        unmet=result["unmet"],
    )
    activate(arm)
    bpy.ops.manikin.import_scenario(filepath=str(SCENARIOS / "cabinet_reach.toml"))
    activate(arm)
    bpy.ops.manikin.import_scenario(filepath=str(SCENARIOS / "deep_squat.toml"), replace=False)
    seen["replace"].update(kept=imported(scene1), arm_alive=arm.name in scene1.objects)


@part("scenes")
def _scenes() -> None:
    """Item 3: a second scene gets obstacles of its own; the first scene's stay, in its own collection."""
    before = imported(scene1)
    scene2 = bpy.data.scenes.new("Line 2")
    arm = bpy.data.objects["worker"]
    shared = arm.users_collection[0]  # the manikin in both scenes (a script cannot make one in a windowless scene)
    scene2.collection.children.link(shared)
    with bpy.context.temp_override(scene=scene2, view_layer=scene2.view_layers[0]):
        scene2.view_layers[0].objects.active = arm
        done = sorted(bpy.ops.manikin.import_scenario(filepath=str(SCENARIOS / "cabinet_reach.toml")))
    mine = [c for c in scene1.collection.children_recursive if any("manikin_imported" in o for o in c.objects)]
    theirs = [c for c in scene2.collection.children_recursive if any("manikin_imported" in o for o in c.objects)]
    seen["scenes"] = dict(
        done=done,
        before=before,
        after=imported(scene1),
        second=len(imported(scene2)),
        collections=[[c.name for c in mine], [c.name for c in theirs]],
        shared=bool({c.name for c in mine} & {c.name for c in theirs}),
        second_in_first=[ob.name for ob in scene2.objects if "manikin_imported" in ob and ob.name in scene1.objects],
    )
    scene2.collection.children.unlink(shared)


def main_panel() -> dict:
    """What the Manikin panel draws for the active object: its lines and the operators it offers."""
    log: list = []
    operators: list[str] = []

    class Recording(Layout):
        def operator(self, idname: str, **kw) -> None:
            operators.append(idname)
            super().operator(idname, **kw)

        def row(self, **kw) -> Recording:
            return self

        column = box = split = row

    panel = bpy.types.MANIKIN_PT_main
    panel.draw(type("Panel", (), {"layout": Recording(log)})(), bpy.context)
    return dict(lines=log, operators=operators)


@part("ghost")
def _ghost() -> None:
    """Item 4: the armature deleted with X: Solve on a leftover target says so; Delete Manikin clears the rest."""
    arm = bpy.data.objects["worker"]
    owned_names = owned(arm)
    activate(arm)
    live_panel = main_panel()
    bpy.ops.object.delete()
    left = [name for name in owned_names if name in scene1.objects]
    target = next(bpy.data.objects[n] for n in owned_names if bpy.data.objects[n].manikin_target.role == "TARGET")
    activate(target)
    solve = error_of(lambda: bpy.ops.manikin.solve_pose())
    activate(target)
    panel = main_panel()
    done = sorted(bpy.ops.manikin.delete_manikin())
    seen["ghost"] = dict(
        panel=panel,
        live_panel=live_panel,
        left_by_x=len(left),
        solve=solve,
        done=done,
        left=[name for name in owned_names if name in bpy.data.objects],
        arm_gone="worker" not in bpy.data.objects,
    )


seen["seconds"] = time.perf_counter() - started
OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
