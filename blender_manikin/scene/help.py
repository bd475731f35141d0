"""The help button in each sidebar panel's header: a ``wm.url_open`` button opening the panel's documentation page.

A panel gets it with one line, ``draw_header_preset = draw_help``; :data:`PAGES` says which page each panel opens
(pages of docs/, as the documentation site serves them). No bpy import: drawing needs only the panel's layout.
"""

from __future__ import annotations

DOCS_URL = "https://manikin.readthedocs.io/en/latest/"  # the documentation site (also the manifest's website)
PAGES = {  # panel class -> page (and section) under DOCS_URL
    "MANIKIN_PT_main": "guide/blender.html#in-the-3d-view",
    "MANIKIN_PT_target": "guide/blender.html#in-the-3d-view",
    "MANIKIN_PT_obstacle": "guide/blender.html#in-the-3d-view",
    "MANIKIN_PT_result": "guide/blender.html#in-the-3d-view",
    "MANIKIN_PT_settings": "guide/blender.html#in-the-3d-view",
    "MANIKIN_PT_motion": "guide/blender.html#motions-in-blender-bake-batch-exports",
    "MANIKIN_PT_retarget": "RETARGET.html",
    "MANIKIN_PT_study": "tutorials/study.html#a-study-from-blender",
    "MANIKIN_PT_motion_ergonomics": "tutorials/motion.html#4-the-same-in-blender",
    "MANIKIN_PT_envelope": "tutorials/envelope.html#from-the-sidebar",
    "MANIKIN_PT_operations": "guide/operations.html#in-blender",
    "MANIKIN_PT_job": "guide/job.html#in-blender",
}
DEFAULT_PAGE = "guide/blender.html"  # a panel not in PAGES


def url_of(panel_name: str) -> str:
    """The documentation URL of the panel class named ``panel_name``."""
    return DOCS_URL + PAGES.get(panel_name, DEFAULT_PAGE)


def draw_help(panel, context) -> None:
    """Draw the help button (a question mark opening the panel's page) at the right of the panel's header."""
    button = panel.layout.operator("wm.url_open", text="", icon="HELP", emboss=False)
    button.url = url_of(type(panel).__name__)
