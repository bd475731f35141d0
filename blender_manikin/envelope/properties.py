"""Settings of the "Reach Envelope" panel, stored on the scene (``Scene.manikin_envelope``): the options of
``python -m solver envelope`` for the active manikin, where the files go, and how the last envelope ended. Imports
only bpy."""

from __future__ import annotations

import bpy
from bpy.props import EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

HANDS = (
    ("right", "Right hand", "The right hand's envelope (TCP hand_r), about the right shoulder"),
    ("left", "Left hand", "The left hand's envelope (TCP hand_l), about the left shoulder"),
    ("both", "Both hands", "One envelope per hand, computed side by side"),
)
FEET = (
    ("planted", "Planted", "Both soles stay where they stand"),
    ("step", "Stepping", "Each sole may slide and turn on the floor, within a step (docs: Stepping)"),
)
HEMISPHERES = (  # solver.envelope.directions.HEMISPHERES (not imported: it loads numpy)
    ("all", "Whole sphere", "Every direction"),
    *((name, name.capitalize(), f"Only the directions of the {name} half") for name in
      ("front", "back", "upper", "lower", "left", "right")),
)  # fmt: skip


class MANIKIN_PG_envelope(bpy.types.PropertyGroup):
    """What envelope to compute for the active manikin, where, and how the last one ended."""

    hand: EnumProperty(name="Hand", items=HANDS, default="right", description="Whose reach")
    feet: EnumProperty(name="Feet", items=FEET, default="planted", description="Feet planted, or allowed to step")
    load_kg: FloatProperty(name="Load (kg)", default=0.0, min=0.0, max=100.0, description="Held in the hand")
    frequency: IntProperty(
        name="Directions", default=3, min=1, max=6,
        description="Geodesic sphere frequency F: 10 F^2 + 2 directions (1: 12, 2: 42, 3: 92, the command's default)",
    )  # fmt: skip
    hemisphere: EnumProperty(name="Half", items=HEMISPHERES, default="all", description="Directions searched")
    tolerance: FloatProperty(
        name="Tolerance", default=0.02, min=0.001, max=0.2, subtype="DISTANCE", unit="LENGTH", precision=3,
        description="Reach resolution: each radius is bisected to this (m)",
    )  # fmt: skip
    sole_scale: FloatProperty(
        name="Sole scale", default=1.0, min=0.1, max=1.0,
        description="Keep the centre of pressure inside the soles scaled by this (1: whole soles, the static limit)",
    )  # fmt: skip
    folder: StringProperty(
        name="Output", subtype="DIR_PATH",
        description="Where envelopes go (empty: manikin_envelopes beside the .blend, or in the temporary folder)",
    )  # fmt: skip
    status: StringProperty(name="Status", description="How the last envelope ended")
    source: PointerProperty(type=bpy.types.Object, name="Manikin", description="The manikin the envelope is for")


classes = (MANIKIN_PG_envelope,)


def attach() -> None:
    """Give every scene the envelope settings (the class registered first)."""
    bpy.types.Scene.manikin_envelope = bpy.props.PointerProperty(type=MANIKIN_PG_envelope)


def detach() -> None:
    """Remove what :func:`attach` added (a running envelope is stopped before: ``operators.unregister``)."""
    del bpy.types.Scene.manikin_envelope
