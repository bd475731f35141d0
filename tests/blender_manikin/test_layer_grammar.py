"""The Blender layer's grammar, checked without bpy: the code calls functions, never our own operators through
``bpy.ops.manikin`` (a dependency no import shows); each feature folder holds what its panel, operators and
headless job need; every module Blender registers gives one ``classes`` tuple."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "blender_manikin"
FEATURES = ("pose", "scenario", "motion", "study", "envelope", "retarget", "operations")


def _dotted(node: ast.AST) -> str:
    parts = []
    while isinstance(node, ast.Attribute):
        parts.append(node.attr)
        node = node.value
    if isinstance(node, ast.Name):
        parts.append(node.id)
    return ".".join(reversed(parts))


def test_no_code_calls_our_own_operators() -> None:
    calls = []
    for path in sorted(PACKAGE.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Attribute) and _dotted(node).startswith("bpy.ops.manikin"):
                calls.append(f"{path.relative_to(ROOT)}:{node.lineno}")
    assert calls == []


def test_every_feature_is_a_folder_with_operators() -> None:
    for name in FEATURES:
        assert (PACKAGE / name / "__init__.py").is_file(), name
        assert (PACKAGE / name / "operators.py").is_file(), name


def test_every_registered_module_has_one_classes_tuple() -> None:
    tree = ast.parse((PACKAGE / "addon.py").read_text(encoding="utf-8"))
    names = next(ast.literal_eval(n.value) for n in tree.body if isinstance(n, ast.Assign)
                 and any(getattr(t, "id", "") == "MODULES" for t in n.targets))  # fmt: skip
    assert {name.split(".")[0] for name in names} == set(FEATURES)
    for name in names:
        module = ast.parse((PACKAGE / (name.replace(".", "/") + ".py")).read_text(encoding="utf-8"))
        assigned = [
            t.id
            for n in module.body
            if isinstance(n, ast.Assign | ast.AnnAssign)
            for t in (n.targets if isinstance(n, ast.Assign) else [n.target])
            if isinstance(t, ast.Name)
        ]
        assert assigned.count("classes") == 1, name
