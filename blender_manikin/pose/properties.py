"""Settings stored in the scene: ``Object.manikin`` on a manikin armature, ``Object.manikin_target`` on empties.

A target empty (``target.<tcp>``) holds a TCP on its world frame; a loop empty (``loop.<tcp>``, parented to
``tcp.<other>``) holds a TCP on another TCP's frame composed with the empty's offset; a load empty
(``load.<tcp>``, parented to ``tcp.<tcp>``) hangs a force at a TCP. All three share one PropertyGroup whose
``role`` says which it is. ``Object.manikin_obstacle`` marks a mesh as an obstacle.

The obstacle shape menu and the manikin's comfort weights follow the solver's registries (obstacle kinds, standard
comfort terms): they are added when the add-on registers (:func:`attach`), not written out here.
"""

import bpy
from bpy.props import (
    BoolProperty,
    BoolVectorProperty,
    EnumProperty,
    FloatProperty,
    FloatVectorProperty,
    IntProperty,
    PointerProperty,
    StringProperty,
)

from ...solver.options import AXES, DEFAULT_LIMITS, MAX_WEIGHT, MIN_WEIGHT
from ..scene.registries import MESH, comfort_settings, shape_items
from ..scene.schema import is_manikin

ROLES = (
    ("NONE", "None", "Not a manikin target"),
    ("TARGET", "Target", "Hold the TCP on this empty's frame"),
    ("LOOP", "Loop", "Hold the TCP on another TCP's frame composed with this empty's offset from it"),
    ("LOAD", "Load", "A force (e.g. a carried mass) acting at the TCP"),
)

PRIORITY_ITEMS = (
    ("AUTO", "Auto", "A support must hold; any other target is met as closely as it can be"),
    ("1", "Must hold", "Priority 1: held like a support, with loops and balance"),
    ("2", "As close as possible", "Priority 2: when it cannot be met, it ends as close as the priority-1 rows allow"),
)


def _resolve_live(rig: bpy.types.Object | None) -> None:
    """A setting changed: re-solve if the manikin is live (property edits do not reach the depsgraph handler)."""
    if rig is not None and rig.type == "ARMATURE" and rig.manikin.live:
        from . import live

        live.request(rig)


def _target_changed(self, context: bpy.types.Context) -> None:
    _resolve_live(self.rig)


def _rig_changed(self, context: bpy.types.Context) -> None:
    _resolve_live(self.id_data)


def _display_changed(self, context: bpy.types.Context) -> None:
    """Show the chosen body (built the first time); a model without a human mesh falls back to the solids."""
    from ...solver.errors import ManikinError
    from ..scene import armature, display

    arm = self.id_data
    try:
        model = armature.model_of(arm)
    except ManikinError:  # the body file is gone: nothing to build from (the panel's actions report it)
        return
    shown = display.show(arm, model, armature.layout_of(model), self.display)
    if shown != self.display:
        self.display = shown


def _is_manikin(_self, obj: bpy.types.Object) -> bool:
    return is_manikin(obj)


class MANIKIN_PG_target(bpy.types.PropertyGroup):
    """What an empty asks of the manikin."""

    role: EnumProperty(name="Role", items=ROLES, default="NONE", update=_target_changed)
    rig: PointerProperty(
        name="Manikin", type=bpy.types.Object, poll=_is_manikin, description="The armature", update=_target_changed
    )
    tcp: StringProperty(
        name="TCP", description="Name of the manikin's TCP this empty acts on, e.g. hand_r", update=_target_changed
    )
    other: StringProperty(
        name="Other TCP", description="Loop: the TCP whose frame the TCP is held to", update=_target_changed
    )
    lock: BoolVectorProperty(
        name="Locked axes",
        size=6,
        default=(True,) * 6,
        description="Constrained axes of the target frame: x y z (position) and rx ry rz (rotation vector)",
        update=_target_changed,
    )
    support: BoolProperty(
        name="Support", description="Contact forces act here (pushing along the target's z)", update=_target_changed
    )
    friction: FloatProperty(
        name="Friction", default=0.6, min=0.0, max=10.0, description="Friction coefficient", update=_target_changed
    )
    weight: FloatProperty(
        name="Weight",
        default=1.0,
        min=MIN_WEIGHT,
        max=MAX_WEIGHT,
        description="Relative weight",
        update=_target_changed,
    )
    priority: EnumProperty(name="Priority", items=PRIORITY_ITEMS, default="AUTO", update=_target_changed)
    enabled: BoolProperty(name="Enabled", default=True, update=_target_changed)
    force: FloatVectorProperty(
        name="Force",
        size=3,
        subtype="XYZ",
        default=(0.0, 0.0, -49.05),
        description="Load: force in N, world frame",
        update=_target_changed,
    )

    def locked_axes(self) -> tuple[str, ...]:
        return tuple(a for a, on in zip(AXES, self.lock, strict=True) if on)

    def priority_number(self) -> int | None:
        """1, 2, or None (by the target's kind)."""
        return None if self.priority == "AUTO" else int(self.priority)


class MANIKIN_PG_obstacle(bpy.types.PropertyGroup):
    """A mesh the manikin keeps clear of (on any mesh object), as the mesh itself or as a simple shape (``shape``:
    one per registered obstacle kind, added by :func:`attach`)."""

    enabled: BoolProperty(name="Obstacle", default=False, description="The manikin keeps clear of this mesh")
    clearance: FloatProperty(
        name="Clearance", default=0.0, min=0.0, max=10.0, subtype="DISTANCE", unit="LENGTH",
        description="Distance the body keeps from the mesh",
    )  # fmt: skip


FEET = (
    ("PLANTED", "Planted", "Each support keeps its own locks; the supports Add Manikin and Add Target make lock all "
     "six axes, so the feet stay where they are and a reach too far ends short"),
    ("SLIDE", "May slide", "Every support may slide and turn on its plane (its x, y and rz are freed, whatever its "
     "locks); how far each slid is reported"),
    ("STEP", "May step", "The feet may step as a person would: each within a step (0.4 x stature) of its target, not "
     "crossed, turned at most 45 deg, in balance and clear of obstacles, only as far as the step helps; each step's "
     "length, direction and turn is reported"),
)  # fmt: skip


def _get_target_index(self) -> int:
    """The row of the active object in the target list (an index into bpy.data.objects), -1 when none."""
    ob = bpy.context.active_object
    return bpy.data.objects.find(ob.name) if ob is not None and ob.manikin_target.role != "NONE" else -1


def _set_target_index(self, index: int) -> None:
    """Clicking a row selects that target empty (only) and makes it active, so its Target panel shows."""
    if not 0 <= index < len(bpy.data.objects):
        return
    ob = bpy.data.objects[index]
    view_layer = bpy.context.view_layer
    if ob.name not in view_layer.objects:
        return
    for other in view_layer.objects.selected:
        other.select_set(False)
    ob.select_set(True)
    view_layer.objects.active = ob


DISPLAYS = (
    ("HUMAN", "Human", "The skinned human: the MakeHuman mesh fitted to the manikin's body"),
    ("CAPSULES", "Capsules", "The solver's collision capsules, riding on the bones"),
    ("SOLIDS", "Solids", "One simple solid per bone, sized by the segment's mass"),
)


class MANIKIN_PG_rig(bpy.types.PropertyGroup):
    """Solver and display settings of one manikin (on its armature object); its comfort weights ``comfort_<term>``,
    one per registered standard comfort term, are added by :func:`attach`."""

    display: EnumProperty(
        name="Display", items=DISPLAYS, default="HUMAN", description="What shows the body", update=_display_changed
    )

    feet: EnumProperty(
        name="Feet",
        items=FEET,
        default="PLANTED",
        description="Whether the supports (the feet) may slide",
        update=_rig_changed,
    )
    target_index: IntProperty(
        name="Target", get=_get_target_index, set=_set_target_index, description="The active row of the target list"
    )
    balance: BoolProperty(
        name="Balance", default=True, description="Static balance with unknown contact forces", update=_rig_changed
    )
    floor: BoolProperty(
        name="Floor", default=True, description="Keep every body part above the floor (z = 0)", update=_rig_changed
    )
    self_collision: BoolProperty(
        name="Self-collision",
        default=True,
        description="Keep hands and forearms out of the trunk, head and thighs, and the shanks apart",
        update=_rig_changed,
    )
    comfort: BoolProperty(
        name="Comfort", default=True, description="Maximise comfort in the constraints' null space", update=_rig_changed
    )
    reduction: BoolProperty(
        name="Variable reduction",
        description="Move the lumbar, thoracic and cervical spine and each hand's grasp as coupled groups",
        update=_rig_changed,
    )
    max_iterations: IntProperty(name="Max iterations", default=100, min=1, max=100000, update=_rig_changed)
    restarts: IntProperty(
        name="Restarts",
        default=1,
        min=0,
        max=10,
        description="A solve that fails starts again from the other side of the joints it left at a limit "
        "(not while dragging live)",
        update=_rig_changed,
    )
    live_iterations: IntProperty(
        name="Live iterations", default=30, min=1, max=1000, description="Iteration limit of each live re-solve"
    )
    live: BoolProperty(
        name="Live",
        default=False,
        description="Re-solve whenever a target, loop or load of this manikin moves",
        update=_rig_changed,
    )
    show_overlay: BoolProperty(
        name="Overlay",
        default=True,
        description="Draw center of mass, support polygon, contact forces and the closest distances to obstacles",
    )
    show_capsules: BoolProperty(
        name="Capsules", default=False, description="Draw the body's collision capsules (of the last solve)"
    )
    bound_motion: BoolProperty(
        name="Bound per-frame change",
        default=True,
        description="Bake Motion: keep every joint near its value in the previous frame (no jumps)",
    )
    max_joint_change: FloatProperty(
        name="Max joint change",
        default=DEFAULT_LIMITS.max_joint_change,
        min=1e-6,
        max=10.0,
        subtype="ANGLE",
        description="Bake Motion: largest change of a joint between consecutive frames",
    )
    max_root_shift: FloatProperty(
        name="Max root shift",
        default=DEFAULT_LIMITS.max_root_shift,
        min=1e-6,
        max=100.0,
        unit="LENGTH",
        description="Bake Motion: largest shift of the pelvis between consecutive frames",
    )


classes = (MANIKIN_PG_target, MANIKIN_PG_obstacle, MANIKIN_PG_rig)


# The settings made from the registries by attach(), kept until detach() removes them: (group, name, property).
_FROM_REGISTRIES: list[tuple[type, str, object]] = []


def _from_registries() -> list[tuple[type, str, object]]:
    """The obstacle shape menu (a registered kind each) and a comfort weight per registered standard comfort term,
    as they are now (:mod:`..scene.registries`)."""
    shape = EnumProperty(name="Shape", items=tuple(shape_items()), default=MESH,
                         description="What the solver keeps clear of")  # fmt: skip
    weights = [(MANIKIN_PG_rig, s.prop, FloatProperty(name=s.title, default=s.default, min=0.0, max=MAX_WEIGHT,
                                                      description=s.description, update=_rig_changed))
               for s in comfort_settings()]  # fmt: skip
    return [(MANIKIN_PG_obstacle, "shape", shape), *weights]


def attach() -> None:
    """Give every object the settings groups (their classes registered first). The shape menu and the comfort
    weights are made now, from the registries: a kind or term registered before the add-on is in them."""
    for group, name, prop in _from_registries():
        setattr(group, name, prop)  # a property added to a registered group (what ``Object.manikin = ...`` does)
        _FROM_REGISTRIES.append((group, name, prop))
    bpy.types.Object.manikin_target = PointerProperty(type=MANIKIN_PG_target)
    bpy.types.Object.manikin_obstacle = PointerProperty(type=MANIKIN_PG_obstacle)
    bpy.types.Object.manikin = PointerProperty(type=MANIKIN_PG_rig)


def detach() -> None:
    """Remove what :func:`attach` added (before the classes are unregistered)."""
    del bpy.types.Object.manikin
    del bpy.types.Object.manikin_obstacle
    del bpy.types.Object.manikin_target
    while _FROM_REGISTRIES:
        group, name, _ = _FROM_REGISTRIES.pop()
        delattr(group, name)
