"""Build and validate the extension zip with the build tool that ships inside the bpy wheel (no Blender binary).

    python -m blender_manikin.build [--output-dir dist]      # from the repository root

writes ``dist/manikin-<version>.zip`` (what ships is set by ``[build]`` in blender_manifest.toml), checks the
manifest's tags against Blender's list and validates the built archive. bpy itself is never imported: the
tool is located through the installed package's files.
"""

from __future__ import annotations

import argparse
import importlib.util
import subprocess
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TOOL = Path("scripts", "addons_core", "bl_pkg", "cli", "blender_ext.py")
TAGS = Path("scripts", "modules", "_bpy_internal", "extensions", "tags.py")


class BuildError(RuntimeError):
    """The build tool is missing or the package did not build or validate."""


def bpy_resources() -> Path:
    """The bpy wheel's versioned resource directory (``.../site-packages/bpy/5.0``), found without importing it."""
    spec = importlib.util.find_spec("bpy")
    if spec is None or not spec.submodule_search_locations:
        raise BuildError("bpy is not installed (pip install -r requirements.txt)")
    for location in spec.submodule_search_locations:
        versions = sorted(p for p in Path(location).glob("[0-9]*.[0-9]*") if (p / TOOL).is_file())
        if versions:
            return versions[-1]
    raise BuildError("the bpy package has no extension build tool (" + str(TOOL) + ")")


def _run(args: list[str]) -> str:
    done = subprocess.run([sys.executable, *args], capture_output=True, text=True, cwd=ROOT)
    output = (done.stdout + done.stderr).strip()
    if done.returncode != 0:
        raise BuildError(f"{Path(args[0]).name} {args[1]} failed:\n{output}")
    return output


def build(output_dir: Path | None = None) -> Path:
    """Validate the manifest, build the zip into ``output_dir`` (default ROOT/dist), validate the zip; its path."""
    resources = bpy_resources()
    tool, tags = str(resources / TOOL), str(resources / TAGS)
    manifest = tomllib.loads((ROOT / "blender_manifest.toml").read_text(encoding="utf-8"))
    out = Path(output_dir) if output_dir else ROOT / "dist"
    out.mkdir(parents=True, exist_ok=True)
    zip_path = out.resolve() / f"{manifest['id']}-{manifest['version']}.zip"
    zip_path.unlink(missing_ok=True)
    _run([tool, "validate", "--valid-tags", tags, str(ROOT)])
    _run([tool, "build", "--source-dir", str(ROOT), "--output-filepath", str(zip_path), "--valid-tags", tags])
    _run([tool, "validate", "--valid-tags", tags, str(zip_path)])
    return zip_path


def install(zip_path: Path, repo: str = "user_default") -> str:
    """Install and enable the zip as a user would (Preferences > Get Extensions > Install from Disk); the add-on's
    module name. Imports bpy: set BLENDER_USER_RESOURCES to a throwaway directory before calling this."""
    import bpy

    manifest_id = zip_path.name.split("-")[0]
    done = bpy.ops.extensions.package_install_files(filepath=str(zip_path), repo=repo, enable_on_install=True)
    module = f"bl_ext.{repo}.{manifest_id}"
    if done != {"FINISHED"} or module not in bpy.context.preferences.addons:
        raise BuildError(f"installing {zip_path} did not enable {module}")
    return module


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m blender_manikin.build", description=__doc__.splitlines()[0])
    parser.add_argument("--output-dir", type=Path, default=None, help="where the zip goes (default: dist/)")
    args = parser.parse_args(argv)
    try:
        path = build(args.output_dir)
    except BuildError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
