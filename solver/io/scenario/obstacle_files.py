"""Mesh obstacles of a scenario as OBJ files beside its TOML: which file each mesh goes to, and its text.

A mesh named ``shelf`` of ``lift.toml`` goes to ``lift_shelf.obj`` (the name's characters other than letters,
digits, ``_`` and ``-`` become ``_``); the table then says ``file = "lift_shelf.obj"`` instead of listing its
vertices and faces. Each file starts with a comment naming its scenario, so writing the scenario again replaces
its own files but never another file of that name: that one is kept and the mesh goes to ``lift_shelf-2.obj``.
"""

from __future__ import annotations

import re
from pathlib import Path

from ...collision import Mesh
from ...collision.mesh_files import obj_text

MAX_NAME = 60  # characters of the obstacle's name kept in a file name
MARK = "Manikin obstacle"  # the first line of our files: "# Manikin obstacle 'shelf' of lift.toml"


def safe_name(name: str) -> str:
    """``name`` as a portable piece of a file name: letters, digits, ``_`` and ``-`` (else "mesh")."""
    return re.sub(r"[^A-Za-z0-9_-]+", "_", name).strip("_")[:MAX_NAME] or "mesh"


def written_for(path: Path, scenario: str) -> bool:
    """Whether ``path`` is a mesh file written for the scenario file named ``scenario`` (its first line says so)."""
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            first = fh.readline().rstrip("\n")
    except OSError:
        return False
    return first.startswith(f"# {MARK} ") and first.endswith(f" of {scenario}")


def _taken(file: Path, scenario: str) -> bool:
    """Whether ``file`` exists and is not one of ``scenario``'s own mesh files (so it must stay as it is)."""
    return (file.exists() or file.is_symlink()) and not written_for(file, scenario)


def mesh_files(path: Path, tables: list[dict]) -> tuple[list[dict], list[tuple[Path, str]]]:
    """The ``[[obstacles]]`` tables of the scenario to be written to ``path`` with each inline mesh moved to a file
    beside it, and the files to write: (tables, [(file path, OBJ text)])."""
    out, files, used = [], [], set()
    for table in tables:
        if table.get("kind") != Mesh.kind or "vertices" not in table:
            out.append(table)
            continue
        base = f"{path.stem}_{safe_name(str(table.get('name', '')))}"
        name, number = f"{base}.obj", 1
        while name.lower() in used or _taken(path.parent / name, path.name):
            number += 1
            name = f"{base}-{number}.obj"
        used.add(name.lower())
        comment = f"{MARK} {str(table.get('name', ''))!r} of {path.name}"
        files.append((path.parent / name, obj_text(table["vertices"], table["faces"], comment)))
        moved = {k: v for k, v in table.items() if k not in ("vertices", "faces")}
        out.append({**{k: moved.pop(k) for k in ("name", "kind") if k in moved}, "file": name, **moved})
    return out, files
