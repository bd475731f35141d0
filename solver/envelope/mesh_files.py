"""Envelope meshes as files: Wavefront OBJ and binary glTF (GLB), written and read with numpy, json and struct only
(no scipy, no matplotlib: the Blender layer reads them in a Blender's own Python).

A file holds named triangle meshes (``balanced``, ``kinematic``) in the manikin's frame (m; the frame of its zero
pose: feet on the floor about the origin, facing -y) and the shoulder the envelope is centred on:

- OBJ: z up as the solver's world (like the obstacle OBJ files); one ``o NAME`` per mesh; a first line
  ``# Manikin reach envelope ...``, a ``# shoulder x y z`` comment line and ``# key: value`` comments describing
  the run.
- GLB: glTF 2.0 is y up, so a point (x, y, z) of the manikin's frame is stored as (x, z, -y); each mesh is a node
  placed at the shoulder (its vertices relative to it) with the run in the scene's ``extras``; its asset's
  generator ``Manikin (python -m solver envelope)``.

:func:`read_envelope` reads only files with those marks: any other OBJ or glTF is refused in one line.
"""

from __future__ import annotations

import json
import struct
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import ResultFileError

GLB_MAGIC, GLB_VERSION = 0x46546C67, 2  # b"glTF"
CHUNK_JSON, CHUNK_BIN = 0x4E4F534A, 0x004E4942
FLOAT, UNSIGNED_INT = 5126, 5125  # glTF component types
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963
COLOURS = {"balanced": (0.15, 0.65, 0.35, 0.45), "kinematic": (0.55, 0.55, 0.6, 0.2)}  # RGBA of each mesh
OBJ_MARK = "# Manikin reach envelope"  # the first line of every envelope OBJ written here
GLB_MARK = "Manikin"  # how the generator of every envelope GLB written here begins
Z_UP_TO_Y_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])  # (x, y, z) -> (x, z, -y)


@dataclass
class EnvelopeMesh:
    """A named triangle mesh: ``vertices`` (V, 3) m in the manikin's frame, ``faces`` (F, 3) 0-based."""

    name: str
    vertices: np.ndarray
    faces: np.ndarray


@dataclass
class EnvelopeFile:
    """What an envelope file holds: its meshes, the shoulder (3,) m in the manikin's frame (the origin when the file
    does not say) and the run's description (``info``: manikin, hand, load, ...)."""

    meshes: list[EnvelopeMesh]
    shoulder: np.ndarray = field(default_factory=lambda: np.zeros(3))
    info: dict = field(default_factory=dict)


def obj_text(envelope: EnvelopeFile) -> str:
    """The OBJ text of ``envelope`` (z up, m; 1-based indices running on over the meshes)."""
    lines = [f"{OBJ_MARK} (python -m solver envelope): m, z up, the manikin's frame"]
    lines += [f"# {key}: {value}" for key, value in envelope.info.items()]
    lines.append("# shoulder {:.9g} {:.9g} {:.9g}".format(*envelope.shoulder))
    first = 1
    for mesh in envelope.meshes:
        lines.append(f"o {mesh.name}")
        lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in mesh.vertices]
        lines += [f"f {a + first} {b + first} {c + first}" for a, b, c in mesh.faces]
        first += len(mesh.vertices)
    return "\n".join(lines) + "\n"


def glb_bytes(envelope: EnvelopeFile) -> bytes:
    """The binary glTF of ``envelope``: per mesh a node at the shoulder, float32 positions and uint32 indices."""
    blob = bytearray()
    views, accessors, meshes, nodes, materials = [], [], [], [], []

    def add_view(data: bytes, target: int) -> int:
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob.extend(data + b"\0" * (-len(data) % 4))  # every view starts on a 4-byte boundary
        return len(views) - 1

    shoulder = Z_UP_TO_Y_UP @ envelope.shoulder
    for mesh in envelope.meshes:
        points = ((mesh.vertices - envelope.shoulder) @ Z_UP_TO_Y_UP.T).astype("<f4")
        indices = np.asarray(mesh.faces, dtype="<u4").ravel()
        accessors.append({"bufferView": add_view(points.tobytes(), ARRAY_BUFFER), "componentType": FLOAT,
                          "count": len(points), "type": "VEC3", "min": points.min(axis=0).tolist(),
                          "max": points.max(axis=0).tolist()})  # fmt: skip
        accessors.append({"bufferView": add_view(indices.tobytes(), ELEMENT_ARRAY_BUFFER),
                          "componentType": UNSIGNED_INT, "count": len(indices), "type": "SCALAR"})  # fmt: skip
        colour = COLOURS.get(mesh.name, (0.8, 0.8, 0.8, 0.5))
        look = {"baseColorFactor": list(colour), "metallicFactor": 0.0}
        materials.append({"name": f"envelope.{mesh.name}", "alphaMode": "BLEND", "doubleSided": True,
                          "pbrMetallicRoughness": look})  # fmt: skip
        primitive = {"attributes": {"POSITION": len(accessors) - 2}, "indices": len(accessors) - 1,
                     "material": len(materials) - 1, "mode": 4}  # fmt: skip
        meshes.append({"name": mesh.name, "primitives": [primitive]})
        nodes.append({"name": mesh.name, "mesh": len(meshes) - 1, "translation": shoulder.tolist()})
    extras = {"shoulder": envelope.shoulder.tolist(), **envelope.info}
    gltf = {
        "asset": {"version": "2.0", "generator": "Manikin (python -m solver envelope)"},
        "scene": 0, "scenes": [{"nodes": list(range(len(nodes))), "extras": extras}], "nodes": nodes,
        "meshes": meshes, "materials": materials, "accessors": accessors, "bufferViews": views,
        "buffers": [{"byteLength": len(blob)}],
    }  # fmt: skip
    text = json.dumps(gltf, separators=(",", ":")).encode("utf-8")
    text += b" " * (-len(text) % 4)
    total = 12 + 8 + len(text) + 8 + len(blob)
    head = struct.pack("<III", GLB_MAGIC, GLB_VERSION, total)
    return head + struct.pack("<II", len(text), CHUNK_JSON) + text + struct.pack("<II", len(blob), CHUNK_BIN) + blob


def read_envelope(path: str | Path) -> EnvelopeFile:
    """The meshes of an envelope ``.obj`` or ``.glb`` file; one ResultFileError line naming the file and what is
    wrong (a mesh file without the marks an envelope written here has: not an envelope)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".obj", ".glb"):
        raise ResultFileError(f"{path}: expected an envelope file ending .obj or .glb, got {path.suffix!r}")
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise ResultFileError(f"{path}: cannot read ({exc.strerror or exc})") from None
    try:
        got = _read_obj(data.decode("utf-8")) if suffix == ".obj" else _read_glb(data)
    except (ValueError, KeyError, IndexError, TypeError, struct.error, UnicodeDecodeError) as exc:
        raise ResultFileError(f"{path}: not a readable envelope file ({exc})") from None
    if got is None:
        raise ResultFileError(f"{path}: not a reach envelope written by Manikin (python -m solver envelope writes "
                              f"them); import other meshes with File > Import")  # fmt: skip
    if not got.meshes or not all(len(m.faces) for m in got.meshes):
        raise ResultFileError(f"{path}: no triangles in the file")
    for mesh in got.meshes:
        if mesh.faces.min() < 0 or mesh.faces.max() >= len(mesh.vertices):
            raise ResultFileError(f"{path}: mesh {mesh.name!r} has a face index outside its vertices")
    return got


def _read_obj(text: str) -> EnvelopeFile | None:
    """Meshes (``o`` starts one), shoulder and ``# key: value`` info of OBJ text; polygons become fans. None
    when the text does not begin with :data:`OBJ_MARK`."""
    if not text.lstrip("\ufeff").startswith(OBJ_MARK):
        return None
    out = EnvelopeFile([])
    vertices: list[list[float]] = []
    name, faces, first = "envelope", [], 0
    for raw in text.splitlines():
        words = raw.split()
        if not words:
            continue
        if words[0] == "#" and len(words) == 5 and words[1] == "shoulder":
            out.shoulder = np.array([float(w) for w in words[2:]])
        elif words[0] == "#" and len(words) >= 2 and words[1].endswith(":"):
            out.info[words[1][:-1]] = " ".join(words[2:])
        elif words[0] == "o":
            _close(out, name, vertices, faces, first)
            name, faces, first = " ".join(words[1:]) or "envelope", [], len(vertices)
        elif words[0] == "v":
            vertices.append([float(w) for w in words[1:4]])
            if len(vertices[-1]) != 3:
                raise ValueError(f"'v' needs x y z, got {raw.strip()!r}")
        elif words[0] == "f":
            corners = [int(w.split("/")[0]) for w in words[1:]]
            corners = [c - 1 if c > 0 else len(vertices) + c for c in corners]
            faces += [[corners[0], corners[k], corners[k + 1]] for k in range(1, len(corners) - 1)]
    _close(out, name, vertices, faces, first)
    return out


def _close(out: EnvelopeFile, name: str, vertices: list, faces: list, first: int) -> None:
    """Add the mesh read so far (its faces renumbered to its own vertices) when it has faces."""
    if faces:
        out.meshes.append(EnvelopeMesh(name, np.array(vertices[first:], float), np.array(faces, np.int64) - first))


def _read_glb(data: bytes) -> EnvelopeFile | None:
    """Meshes of a GLB (positions and triangle indices of each node's mesh, back in the manikin's frame); None when
    its generator is not :data:`GLB_MARK`'s."""
    magic, version, total = struct.unpack_from("<III", data, 0)
    if magic != GLB_MAGIC or version != 2 or total > len(data):
        raise ValueError("not a glTF 2.0 binary (GLB) file")
    json_length, kind = struct.unpack_from("<II", data, 12)
    if kind != CHUNK_JSON:
        raise ValueError("the first chunk is not JSON")
    gltf = json.loads(data[20 : 20 + json_length])
    if not str(gltf.get("asset", {}).get("generator", "")).startswith(GLB_MARK):
        return None
    start = 20 + json_length
    bin_length, kind = struct.unpack_from("<II", data, start)
    if kind != CHUNK_BIN:
        raise ValueError("the second chunk is not binary data")
    blob = data[start + 8 : start + 8 + bin_length]
    scene = gltf["scenes"][gltf.get("scene", 0)]
    extras = dict(scene.get("extras", {}))
    out = EnvelopeFile([], np.asarray(extras.pop("shoulder", [0.0, 0.0, 0.0]), float), extras)
    for index in scene["nodes"]:
        node = gltf["nodes"][index]
        place = np.asarray(node.get("translation", [0.0, 0.0, 0.0]), float)
        for primitive in gltf["meshes"][node["mesh"]]["primitives"]:
            points = _accessor(gltf, blob, primitive["attributes"]["POSITION"], "<f4", 3) + place
            faces = _accessor(gltf, blob, primitive["indices"], "<u4", 1).reshape(-1, 3).astype(np.int64)
            out.meshes.append(EnvelopeMesh(node.get("name", "envelope"), points @ Z_UP_TO_Y_UP, faces))
    return out


def _accessor(gltf: dict, blob: bytes, index: int, dtype: str, width: int) -> np.ndarray:
    """The (count, width) array of accessor ``index`` (tightly packed, as written here)."""
    accessor = gltf["accessors"][index]
    view = gltf["bufferViews"][accessor["bufferView"]]
    offset = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    count = accessor["count"]
    end = offset + count * width * 4
    if end > len(blob) or end > view.get("byteOffset", 0) + view["byteLength"]:
        raise ValueError(f"accessor {index} runs past its buffer view")
    values = np.frombuffer(blob, dtype=dtype, count=count * width, offset=offset)
    return values.reshape(count, width).astype(float if dtype == "<f4" else np.int64)
