"""Helpers of the session scripts (run by Blender-equivalent Pythons, next to this file on their path)."""

from __future__ import annotations


def error_of(call) -> str:
    """The error an operator reported (a script sees an ERROR report as RuntimeError), or "" if none."""
    try:
        call()
    except RuntimeError as exc:
        return str(exc)
    return ""
