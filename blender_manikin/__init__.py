"""The Blender layer of Manikin (bpy only: scene <-> solver translation, operators, panels, handlers, batch).

The add-on's operators and panels are built in a later issue; until then the extension registers nothing.
"""

classes: tuple = ()


def register() -> None:
    """Register the add-on's classes with Blender."""
    import bpy

    for cls in classes:
        bpy.utils.register_class(cls)


def unregister() -> None:
    """Unregister everything :func:`register` added."""
    import bpy

    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
