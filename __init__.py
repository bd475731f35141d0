"""Blender extension entry point: registration lives in blender_manikin (imported relatively)."""

if __package__:  # pytest imports this file as a plain module when the checkout's folder is no Python name
    from .blender_manikin import register, unregister

    __all__ = ["register", "unregister"]
