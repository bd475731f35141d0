"""The add-on's settings follow the solver's registries, run by tests/blender/test_registries.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/registries_session.py <zip> <out.json> <work dir>

the shape menu and the comfort weights as installed; a made-up obstacle kind (a sphere by another name) and a
made-up standard comfort term registered in the installed solver (what one ``register`` line does); a scenario with
the new kind imported while the add-on still has its old menu (one line); the add-on disabled and enabled again;
then the menu and the weights, an object marked as the new kind, the new weight set, the problem read from the
scene, the settings panel, a solve, an export and an import of the scenario; the made-up ones removed and the
add-on enabled again. Writes what it saw to JSON; bpy is imported here only.
"""

from __future__ import annotations

import importlib
import json
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from session_tools import Layout, error_of, install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
seen: dict = {}

import bpy  # noqa: E402

addon_utils = importlib.import_module("addon_utils")  # on the path once bpy is imported
module = install(ZIP)
kinds = importlib.import_module(module + ".solver.collision.kinds")
standard = importlib.import_module(module + ".solver.comfort.standard")
ComfortTerm = importlib.import_module(module + ".solver.comfort.base").ComfortTerm
problem_io = importlib.import_module(module + ".blender_manikin.scene.problem_io")
addon = importlib.import_module(module + ".blender_manikin.addon")


@dataclass(frozen=True, eq=False)
class Pebble(kinds.Sphere):
    """Made up for the test: a sphere under another kind's name."""

    kind = "pebble_test"
    description = "A made-up ball (test)"


class Idle(ComfortTerm):
    """Made up for the test: costs nothing."""

    name = "idle_test"
    description = "nothing at all (test)"

    def __init__(self, model) -> None:
        pass

    def cost(self, state) -> float:
        return 0.0

    def derivatives(self, state, weight: float) -> tuple:
        return np.zeros(state.n_x), np.zeros(state.n_x)


def settings_of(pointer: str):
    """The RNA of a settings group on objects (``manikin``, ``manikin_obstacle``)."""
    return bpy.types.Object.bl_rna.properties[pointer].fixed_type


def menus() -> dict:
    """The shape menu's items and the manikin's comfort weights (name, default, description), as registered now."""
    items = settings_of("manikin_obstacle").properties["shape"].enum_items
    shapes = [[i.identifier, i.name, i.description] for i in items]
    weights = [[p.identifier, p.name, p.default, p.description] for p in settings_of("manikin").properties
               if p.identifier.startswith("comfort_")]  # fmt: skip
    return dict(shapes=shapes, weights=weights)


def enable_again() -> None:
    addon_utils.disable(module, refresh_handled=True)
    addon_utils.enable(module, default_set=True, refresh_handled=True)


class PropLayout(Layout):
    """The recording layout, also noting each property drawn."""

    def row(self, **kw) -> PropLayout:
        return PropLayout(self.log)

    column = box = split = row

    def prop(self, data, name: str, **kw) -> None:
        super().prop(data, name, **kw)
        self.log.append("prop:" + name)


bpy.ops.manikin.add_manikin(preset="male_50")
arm = bpy.context.active_object
for tcp in ("foot_l", "foot_r", "hand_r"):
    bpy.context.view_layer.objects.active = arm
    bpy.ops.manikin.add_target(tcp=tcp)
bpy.context.view_layer.objects.active = arm
seen["before"] = menus()

# Registered after the add-on: its menu does not have the new kind yet; importing a scenario with one is one line.
kinds.register(Pebble)
standard.register(Idle, 0.25)
seen["exported_early"] = sorted(bpy.ops.manikin.export_scenario(filepath=str(WORK / "early.toml")))
early = (WORK / "early.toml").read_text(encoding="utf-8")
(WORK / "pebble.toml").write_text(early + '\n[[obstacles]]\nname = "stone"\nkind = "pebble_test"\n'
                                  'center = [3.0, 3.0, 0.5]\nradius = 0.2\n', encoding="utf-8")  # fmt: skip
seen["early_weights"] = dict(problem_io.read_problem(arm).problem.comfort.weights)  # the new term at its default
bpy.context.view_layer.objects.active = arm
objects = sorted(ob.name for ob in bpy.data.objects)
seen["too_early"] = error_of(lambda: bpy.ops.manikin.import_scenario(filepath=str(WORK / "pebble.toml")))
seen["unchanged"] = sorted(ob.name for ob in bpy.data.objects) == objects

enable_again()
seen["after"] = menus()
bpy.ops.mesh.primitive_uv_sphere_add(radius=0.15, location=(2.0, 2.0, 0.5))
pebble = bpy.context.active_object
pebble.name = "pebble"
pebble.manikin_obstacle.enabled, pebble.manikin_obstacle.shape = True, "PEBBLE_TEST"
arm.manikin.comfort_idle_test = 2.0
bpy.context.view_layer.objects.active = arm
problem = problem_io.read_problem(arm).problem
seen["read"] = dict(kinds={ob.name: type(ob).__name__ for ob in problem.obstacles},
                    weights=dict(problem.comfort.weights))  # fmt: skip
log: list = []
for panel in addon.panels():
    if panel.__name__ == "MANIKIN_PT_settings" and panel.poll(bpy.context):
        panel.draw(type("Panel", (), {"layout": PropLayout(log)})(), bpy.context)
seen["panel"] = [line.removeprefix("prop:") for line in log if line.startswith("prop:comfort_")]
seen["solve"] = sorted(bpy.ops.manikin.solve_pose())
seen["comfort_parts"] = json.loads(arm["manikin_result"]).get("comfort_parts")
seen["export"] = sorted(bpy.ops.manikin.export_scenario(filepath=str(WORK / "registered.toml")))

for ob in list(bpy.data.objects):  # an emptied scene, the scenario imported: the shape and the weight come back
    bpy.data.objects.remove(ob, do_unlink=True)
seen["import"] = sorted(bpy.ops.manikin.import_scenario(filepath=str(WORK / "registered.toml")))
lifter = bpy.context.active_object
seen["imported"] = dict(shape=bpy.data.objects["pebble"].manikin_obstacle.shape,
                        weight=lifter.manikin.comfort_idle_test)  # fmt: skip

# The made-up ones gone and the add-on enabled again: the menu and the weights as installed.
del kinds.KINDS[Pebble.kind], standard.STANDARD_TERMS[Idle.name]
enable_again()
seen["restored"] = menus()
bpy.context.view_layer.objects.active = lifter
seen["stale_shape"] = bpy.data.objects["pebble"].manikin_obstacle.shape  # saved as the 7th item, now none
seen["stale_solve"] = error_of(lambda: bpy.ops.manikin.solve_pose())
bpy.data.objects.remove(bpy.data.objects["pebble"], do_unlink=True)
seen["restored_weights"] = dict(problem_io.read_problem(lifter).problem.comfort.weights)

OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
