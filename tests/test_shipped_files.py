"""What the extension zip ships, checked without building it: the manifest's ``paths_exclude_pattern`` applied to
this tree by the build tool's own matcher (from the bpy wheel) as its build walks the tree. Only the add-on goes in
(the entry ``__init__.py``, the manifest, LICENSE, ``blender_manikin/`` without ``dev/``, ``solver/`` without
``bench/``, ``presets/``): no developer tool, benchmark, test or doc; and nothing shipped imports a developer tool
or benchmark. The built zip itself is checked the same way in tests/blender/test_session.py.
"""

from __future__ import annotations

import ast
import importlib.util
import os
import tomllib
from pathlib import Path
from types import ModuleType

import pytest

from blender_manikin.dev.build import ROOT, TOOL, bpy_resources

SHIPPED_ROOTS = {"__init__.py", "blender_manifest.toml", "LICENSE", "blender_manikin", "solver", "presets"}
NEVER_SHIPPED = ("blender_manikin/dev/", "bench/", "tests/", "docs/", "dist/", "out/", "wheels/", ".")
NEEDED = ("__init__.py", "blender_manifest.toml", "LICENSE", "blender_manikin/__init__.py", "blender_manikin/batch.py",
          "blender_manikin/addon.py", "blender_manikin/scene/schema.py", "solver/__init__.py",
          "solver/cli/main.py", "presets/manikins/male_50.toml", "presets/body_mesh/mpfb2_base.npz",
          "presets/body_mesh/mpfb2_rigs.json", "presets/body_mesh/LICENSE.md")  # fmt: skip
DEVELOPMENT = ("blender_manikin.dev", "bench")  # packages that stay in the checkout


def _build_tool() -> ModuleType:
    spec = importlib.util.spec_from_file_location("blender_ext", bpy_resources() / TOOL)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def shipped_files() -> list[str]:
    """The files the build puts in the zip (besides the manifest's wheels), as the tool walks the tree: directories
    tested with a trailing slash and skipped whole when excluded, symbolic links skipped."""
    patterns = tomllib.loads((ROOT / "blender_manifest.toml").read_text(encoding="utf-8"))["build"]
    excluded = _build_tool().PathPatternMatch(patterns["paths_exclude_pattern"])
    found = []
    for folder, dirs, files in os.walk(ROOT):
        rel = Path(folder).relative_to(ROOT)
        skipped = [d for d in dirs if Path(folder, d).is_symlink() or excluded.test_path(f"{(rel / d).as_posix()}/")]
        dirs[:] = [d for d in dirs if d not in skipped]
        for name in files:
            path = (rel / name).as_posix()
            if not Path(folder, name).is_symlink() and not excluded.test_path(path):
                found.append(path)
    return sorted(found)


@pytest.fixture(scope="module")
def shipped() -> list[str]:
    return shipped_files()


def test_only_the_add_on_ships(shipped: list[str]) -> None:
    assert set(NEEDED) <= set(shipped)
    for path in shipped:
        assert path.split("/")[0] in SHIPPED_ROOTS, path
        assert not path.startswith(NEVER_SHIPPED) and "__pycache__" not in path, path
        assert not path.endswith(".md") or Path(path).name.startswith("LICENSE"), path  # docs stay home


def _imported(tree: ast.Module, package: list[str]) -> list[tuple[str, bool]]:
    """(absolute module name, inside a function) of every import in ``tree``, relative ones resolved."""
    found = []

    def visit(node: ast.AST, in_function: bool) -> None:
        for child in ast.iter_child_nodes(node):
            inside = in_function or isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef)
            if isinstance(child, ast.Import):
                found.extend((alias.name, inside) for alias in child.names)
            elif isinstance(child, ast.ImportFrom):
                base = package[: len(package) - child.level + 1] if child.level else []
                module = ".".join(base + ([child.module] if child.module else []))
                found.extend((f"{module}.{alias.name}".strip("."), inside) for alias in child.names)
            elif isinstance(child, ast.Call) and getattr(child.func, "attr", "") == "import_module" and child.args:
                if isinstance(child.args[0], ast.Constant):
                    found.append((str(child.args[0].value), inside))
            visit(child, inside)

    visit(tree, False)
    return found


def test_nothing_shipped_imports_a_developer_tool_or_benchmark(shipped: list[str]) -> None:
    for path in (p for p in shipped if p.endswith(".py")):
        parts = path.removesuffix(".py").split("/")
        package = parts[:-1]  # the repository root is the extension's package itself
        tree = ast.parse((ROOT / path).read_text(encoding="utf-8"))
        for module, _ in _imported(tree, package):
            is_development = any(module == d or module.startswith(d + ".") for d in DEVELOPMENT)
            assert not is_development, f"{path} imports {module}"


def test_the_rigging_helpers_need_no_blender() -> None:
    for path in sorted((ROOT / "blender_manikin" / "rigging").glob("*.py")):
        rel = path.relative_to(ROOT)
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for module, _ in _imported(tree, list(rel.parent.parts)):
            assert module.split(".")[0] not in {"bpy", "mathutils", "gpu", "bpy_extras"}, f"{rel} imports {module}"
