"""Blender extension entry point: registration lives in blender_manikin (imported relatively)."""

from .blender_manikin import register, unregister

__all__ = ["register", "unregister"]
