"""Build and validate the extension zips with the build tool that ships inside the bpy wheel (no Blender binary).

    python -m blender_manikin.dev.build [--output-dir dist] [--platform linux-x64]   # from the repository root

fetches the wheels the manifest lists (scipy, matplotlib and what it needs for PNG pictures, per platform) from the
package registry into ``wheels/`` unless they are there already, then writes one zip per platform,
``dist/manikin-<version>-<platform>.zip`` (windows_x64, macos_arm64, macos_x64, linux_x64), each with only its
platform's wheels, checks the manifest's tags against Blender's list and validates every zip. bpy itself is never
imported: the tool is found through the installed package's files.
"""

from __future__ import annotations

import argparse
import importlib.util
import platform as host
import subprocess
import sys
import tomllib
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]  # the repository (extension) root
WHEELS = ROOT / "wheels"
TOOL = Path("scripts", "addons_core", "bl_pkg", "cli", "blender_ext.py")
TAGS = Path("scripts", "modules", "_bpy_internal", "extensions", "tags.py")
PYTHON = "3.11"  # Blender 4.2 to 5.0 all run CPython 3.11


class BuildError(RuntimeError):
    """The build tool or a wheel is missing, or the package did not build or validate."""


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


def this_platform() -> str:
    """This machine's Blender platform name: linux-x64, windows-x64, macos-arm64 or macos-x64."""
    system = {"darwin": "macos", "win32": "windows"}.get(sys.platform, sys.platform)
    machine = host.machine().lower()
    return f"{system}-{'arm64' if machine in ('arm64', 'aarch64') else 'x64'}"


def manifest() -> dict:
    return tomllib.loads((ROOT / "blender_manifest.toml").read_text(encoding="utf-8"))


def _platform_tags(wheel: str) -> tuple[str, ...]:
    """The platform tags of a wheel file name (``manylinux_2_17_x86_64.manylinux2014_x86_64`` is two)."""
    return tuple(Path(wheel).stem.split("-")[-1].split("."))


def fetch_wheels(cache: Path = WHEELS) -> list[Path]:
    """Every wheel of the manifest in ``cache``, downloaded with pip for its platform where missing."""
    wanted = [cache / Path(w).name for w in manifest().get("wheels", [])]
    missing: dict[tuple[str, ...], list[str]] = defaultdict(list)
    for path in wanted:
        if not path.is_file():
            name, version = path.name.split("-")[:2]
            missing[_platform_tags(path.name)].append(f"{name}=={version}")
    for tags, requirements in missing.items():
        platforms = [arg for tag in tags for arg in ("--platform", tag)]  # "any": pure Python, not this machine's
        command = [sys.executable, "-m", "pip", "download", "--quiet", "--no-deps", "--only-binary=:all:",
                   "--python-version", PYTHON, *platforms, "--dest", str(cache), *requirements]  # fmt: skip
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0:
            raise BuildError(f"pip download {' '.join(requirements)} failed:\n{done.stderr.strip()[-2000:]}")
    absent = [p.name for p in wanted if not p.is_file()]
    if absent:
        raise BuildError(f"the registry gave other files than the manifest lists; missing: {', '.join(absent)}")
    return wanted


def _run(args: list[str]) -> str:
    done = subprocess.run([sys.executable, *args], capture_output=True, text=True, cwd=ROOT)
    output = (done.stdout + done.stderr).strip()
    if done.returncode != 0:
        raise BuildError(f"{Path(args[0]).name} {args[1]} failed:\n{output}")
    return output


def build(output_dir: Path | None = None) -> dict[str, Path]:
    """Fetch the wheels, validate the manifest, build one zip per platform into ``output_dir`` (default
    ROOT/dist) and validate each; {platform: zip path}."""
    resources = bpy_resources()
    tool, tags = str(resources / TOOL), str(resources / TAGS)
    info = manifest()
    fetch_wheels()
    out = (Path(output_dir) if output_dir else ROOT / "dist").resolve()
    out.mkdir(parents=True, exist_ok=True)
    zips = {p: out / f"{info['id']}-{info['version']}-{p.replace('-', '_')}.zip" for p in info["platforms"]}
    for path in zips.values():
        path.unlink(missing_ok=True)
    _run([tool, "validate", "--valid-tags", tags, str(ROOT)])
    _run([tool, "build", "--source-dir", str(ROOT), "--output-dir", str(out), "--split-platforms",
          "--valid-tags", tags])  # fmt: skip
    for platform, path in zips.items():
        if not path.is_file():
            raise BuildError(f"the build wrote no zip for {platform} ({path.name})")
        _run([tool, "validate", "--valid-tags", tags, str(path)])
    return zips


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
    parser = argparse.ArgumentParser(prog="python -m blender_manikin.dev.build", description=__doc__.splitlines()[0])
    parser.add_argument("--output-dir", type=Path, default=None, help="where the zips go (default: dist/)")
    parser.add_argument("--platform", help="print only this platform's zip (e.g. linux-x64); all are built")
    args = parser.parse_args(argv)
    try:
        zips = build(args.output_dir)
        if args.platform is not None and args.platform not in zips:
            raise BuildError(f"--platform {args.platform}: not one of {', '.join(zips)}")
    except BuildError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    for platform, path in zips.items():
        if args.platform in (None, platform):
            print(path if args.platform else f"{path}  ({path.stat().st_size / 1e6:.1f} MB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
