"""The manifest's website and permissions: present, as the extensions platform asks, and the manifest valid by
Blender's own build tool (run from the bpy wheel's files, bpy never imported)."""

from __future__ import annotations

import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from blender_manikin.dev.build import TAGS, TOOL, BuildError, bpy_resources
from blender_manikin.scene.help import DOCS_URL, PAGES

ROOT = Path(__file__).resolve().parents[1]
MANIFEST = tomllib.loads((ROOT / "blender_manifest.toml").read_text(encoding="utf-8"))


def test_website_is_the_docs_site_the_help_buttons_open() -> None:
    assert MANIFEST["website"] == DOCS_URL and DOCS_URL.startswith("https://") and DOCS_URL.endswith("/")


def test_permissions_say_what_files_the_add_on_touches() -> None:
    files = MANIFEST["permissions"]["files"]
    assert "scenario" in files and "exports" in files
    assert len(files) <= 64 and not files.endswith(".")  # the platform's limits for a permission's reason


def test_help_pages_exist_in_the_docs() -> None:
    for page in set(PAGES.values()):
        name, _, anchor = page.partition("#")
        source = ROOT / "docs" / name.replace(".html", ".md")
        assert source.is_file(), page
        if anchor:  # a heading whose MyST slug is the anchor
            slugs = {_slug(line.lstrip("#")) for line in source.read_text(encoding="utf-8").splitlines()
                     if line.startswith(("## ", "### "))}  # fmt: skip  (conf.py: anchors down to ###)
            assert anchor in slugs, page


def _slug(heading: str) -> str:
    kept = "".join(c for c in heading.strip().lower() if c.isalnum() or c in " -_")
    return "-".join(kept.split())


def test_blender_s_build_tool_validates_the_manifest() -> None:
    try:
        resources = bpy_resources()
    except BuildError as exc:
        pytest.skip(str(exc))
    args = [sys.executable, str(resources / TOOL), "validate", "--valid-tags", str(resources / TAGS), str(ROOT)]
    done = subprocess.run(args, capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
