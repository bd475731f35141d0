"""Settings of the "Population Study" panel, stored on the scene (``Scene.manikin_study``): what to study, where,
and the rows of the last study, so the table stays with the .blend. Imports only bpy and light solver modules."""

from __future__ import annotations

import bpy
from bpy.props import BoolProperty, CollectionProperty, EnumProperty, IntProperty, PointerProperty, StringProperty

from ...solver.presets import PRESETS_DIR

FAMILIES = PRESETS_DIR / "families"  # the shipped manikin families
FOLDER = "FOLDER"  # the family choice that reads a folder of the user's
VARY = (
    ("NONE", "Nothing", "Every member on the targets as they are"),
    ("z", "Target height", "Add each value (m) to the height of the chosen targets"),
    ("x", "Target x", "Add each value (m) to the x of the chosen targets (armature space)"),
    ("y", "Target y", "Add each value (m) to the y of the chosen targets (armature space; the manikin faces -y)"),
)


def family_items() -> list[tuple[str, str, str]]:
    """The shipped families (presets/families/NAME with a family.toml), then "a folder of your own"."""
    names = sorted(p.name for p in FAMILIES.iterdir() if (p / "family.toml").is_file()) if FAMILIES.is_dir() else []
    shipped = [(n, n, f"The shipped family presets/families/{n}") for n in names]
    return shipped + [(FOLDER, "Folder...", "A family folder written by `python -m solver family`")]


class MANIKIN_PG_study_row(bpy.types.PropertyGroup):
    """One run of the last study, as the table shows it (``name``: the manikin, for the list's filter)."""

    run_id: StringProperty(name="Run id")
    role: StringProperty(name="Role")
    parameters: StringProperty(name="Parameters")
    status: StringProperty(name="Status")
    converged: BoolProperty(name="Converged")
    scores: StringProperty(name="Scores", description="The peak of each score column (tab-separated)")
    l4_l5: StringProperty(name="L4/L5 compression (N)")
    shortfall: StringProperty(name="Shortfall (mm)")


class MANIKIN_PG_study(bpy.types.PropertyGroup):
    """What to study, where, and the last study's rows."""

    family: EnumProperty(name="Family", items=family_items(), description="The manikins of the study")
    family_folder: StringProperty(name="Folder", subtype="DIR_PATH", description="A folder of `solver family`")
    vary: EnumProperty(name="Vary", items=VARY, default="NONE", description="One parameter the study varies")
    tcps: StringProperty(name="Targets", default="hand_r", description="TCP names of the targets moved (spaces)")
    values: StringProperty(name="Values", default="-0.1, 0, 0.1", description="Offsets in m, separated by commas")
    workers: IntProperty(name="Workers", default=0, min=0, max=256, description="Processes (0: all cores but one)")
    folder: StringProperty(
        name="Output", subtype="DIR_PATH",
        description="Where studies go (empty: manikin_studies beside the .blend, or in the temporary folder)",
    )  # fmt: skip
    status: StringProperty(name="Status", description="How the last study ended")
    study_file: StringProperty(name="Study file", description="The study the rows come from")
    source: PointerProperty(type=bpy.types.Object, name="Manikin", description="The armature the study ran on")
    score_titles: StringProperty(name="Score columns", description="The table's score columns (tab-separated)")
    rows: CollectionProperty(type=MANIKIN_PG_study_row)
    row_index: IntProperty(name="Row", default=0, min=0)


classes = (MANIKIN_PG_study_row, MANIKIN_PG_study)


def attach() -> None:
    """Give every scene the study settings (the classes registered first)."""
    bpy.types.Scene.manikin_study = bpy.props.PointerProperty(type=MANIKIN_PG_study)


def detach() -> None:
    """Remove what :func:`attach` added (a running study is stopped before: ``operators.unregister``)."""
    del bpy.types.Scene.manikin_study
