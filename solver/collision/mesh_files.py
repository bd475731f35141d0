"""Triangle meshes from files: Wavefront OBJ, STL (binary or ASCII) and PLY (ASCII or binary), and an OBJ writer.

Only geometry is read (positions and faces); polygons are split into triangle fans; STL's separate triangles are
welded at identical corners. Units are taken as metres. Errors are one line naming the file and the line or
part that is wrong (:class:`solver.errors.ScenarioError`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import ScenarioError
from .triangle_frames import degenerate_faces

_PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2", "ushort": "u2",
    "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4", "float": "f4", "float32": "f4",
    "double": "f8", "float64": "f8",
}  # fmt: skip


def _fan(polygon: list[int]) -> list[list[int]]:
    return [[polygon[0], polygon[i], polygon[i + 1]] for i in range(1, len(polygon) - 1)]


def _obj_index(token: str, count: int, where: str) -> int:
    try:
        i = int(token.split("/")[0])
    except ValueError:
        raise ScenarioError(f"{where}: expected a vertex index, got {token!r}") from None
    if i == 0 or not -count <= i <= count:
        raise ScenarioError(f"{where}: vertex index {i} out of range (the file has {count} vertices so far)")
    return i - 1 if i > 0 else count + i


def _read_obj(path: Path, text: str) -> tuple[np.ndarray, np.ndarray, list[int], list[int]]:
    """(vertices, triangles, and the file's line of each vertex and of each triangle, for messages)."""
    vertices: list[list[float]] = []
    faces: list[list[int]] = []
    vertex_lines: list[int] = []
    face_lines: list[int] = []
    for number, raw in enumerate(text.splitlines(), start=1):
        words = raw.split("#", 1)[0].split()
        where = f"{path}: line {number}"
        if not words:
            continue
        if words[0] == "v":
            try:
                vertices.append([float(x) for x in words[1:4]])
            except ValueError:
                raise ScenarioError(f"{where}: expected 'v x y z' with numbers, got {raw.strip()!r}") from None
            if len(vertices[-1]) != 3:
                raise ScenarioError(f"{where}: expected 'v x y z', got {raw.strip()!r}")
            vertex_lines.append(number)
        elif words[0] == "f":
            polygon = [_obj_index(token, len(vertices), where) for token in words[1:]]
            if len(polygon) < 3:
                raise ScenarioError(f"{where}: a face needs at least 3 vertices, got {raw.strip()!r}")
            fan = _fan(polygon)
            faces += fan
            face_lines += [number] * len(fan)
    points = np.array(vertices, dtype=float).reshape(-1, 3)
    return points, np.array(faces, dtype=np.int64).reshape(-1, 3), vertex_lines, face_lines


def _obj_lines_check(path: Path, vertices: np.ndarray, faces: np.ndarray, vertex_lines: list[int],
                     face_lines: list[int]) -> None:  # fmt: skip
    """An OBJ's non-finite vertex or degenerate triangle, named by its line in the file."""
    bad = np.flatnonzero(~np.isfinite(vertices).all(axis=1))
    if bad.size:
        raise ScenarioError(f"{path}: line {vertex_lines[bad[0]]}: expected finite numbers, got "
                            f"{vertices[bad[0]].tolist()}")  # fmt: skip
    flat = np.flatnonzero(degenerate_faces(vertices, faces))
    if flat.size:
        raise ScenarioError(f"{path}: line {face_lines[flat[0]]}: degenerate triangle (zero area), {flat.size} such "
                            "face(s)")  # fmt: skip


def _weld(corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Triangle corners (F, 3, 3) -> (unique vertices, faces) joining corners with identical coordinates."""
    vertices, inverse = np.unique(corners.reshape(-1, 3), axis=0, return_inverse=True)
    return vertices.astype(float), inverse.reshape(-1, 3).astype(np.int64)


def _read_stl(path: Path, data: bytes) -> tuple[np.ndarray, np.ndarray]:
    if len(data) >= 84:
        count = int(np.frombuffer(data, dtype="<u4", count=1, offset=80)[0])
        if len(data) == 84 + 50 * count:
            record = np.dtype([("normal", "<f4", 3), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])
            corners = np.frombuffer(data, dtype=record, count=count, offset=84)["corners"]
            return _weld(corners.astype(float))
    if not data.lstrip().startswith(b"solid"):
        raise ScenarioError(f"{path}: not an STL file (neither binary with a matching size nor ASCII 'solid')")
    corners, loop = [], []
    for number, raw in enumerate(data.decode("utf-8", errors="replace").splitlines(), start=1):
        words = raw.split()
        if words[:1] == ["vertex"]:
            try:
                loop.append([float(x) for x in words[1:]])
            except ValueError:
                loop.append([])
            if len(loop[-1]) != 3:
                raise ScenarioError(f"{path}: line {number}: expected 'vertex x y z', got {raw.strip()!r}")
        elif words[:1] == ["endloop"]:
            if len(loop) != 3:
                raise ScenarioError(f"{path}: line {number}: a facet needs 3 vertices, got {len(loop)}")
            corners.append(loop)
            loop = []
    return _weld(np.array(corners, dtype=float).reshape(-1, 3, 3))


def _ply_header(path: Path, data: bytes) -> tuple[str, list[tuple[str, int, list[tuple[str, ...]]]], int]:
    """(format, elements as (name, count, properties), byte offset of the body)."""
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise ScenarioError(f"{path}: not a PLY file (expected 'ply' ... 'end_header')")
    body = data.index(b"\n", end) + 1 if b"\n" in data[end:] else len(data)
    fmt, elements = "", []
    for number, raw in enumerate(data[:end].decode("ascii", errors="replace").splitlines(), start=1):
        words = raw.split()
        if words[:1] == ["format"] and len(words) >= 2:
            fmt = words[1]
        elif words[:1] == ["element"] and len(words) == 3 and words[2].isdigit():
            elements.append((words[1], int(words[2]), []))
        elif words[:1] == ["property"] and elements:
            known = all(w in _PLY_TYPES for w in words[1:-1] if w != "list")
            if len(words) < 3 or not known:
                raise ScenarioError(f"{path}: line {number}: unsupported property {raw.strip()!r}")
            elements[-1][2].append(tuple(words[1:]))
        elif words and words[0] not in ("ply", "comment", "obj_info"):
            raise ScenarioError(f"{path}: line {number}: unexpected header line {raw.strip()!r}")
    if fmt not in ("ascii", "binary_little_endian", "binary_big_endian"):
        raise ScenarioError(f"{path}: unknown PLY format {fmt!r}")
    names = [e[0] for e in elements]
    if "vertex" not in names or "face" not in names:
        raise ScenarioError(f"{path}: a PLY mesh needs 'element vertex' and 'element face', got {names}")
    return fmt, elements, body


def _ply_columns(path: Path, props: list[tuple[str, ...]]) -> tuple[list[int], int]:
    """Positions of x, y, z among a vertex element's properties, and of the face index list."""
    names = [p[-1] for p in props]
    if all(n in names for n in "xyz"):
        return [names.index(n) for n in "xyz"], -1
    lists = [i for i, p in enumerate(props) if p[0] == "list" and p[-1] in ("vertex_indices", "vertex_index")]
    if not lists:
        raise ScenarioError(f"{path}: PLY needs vertex properties x, y, z and a face list 'vertex_indices'")
    return [], lists[0]


def _ply_ascii(path: Path, data: bytes, elements, body: int) -> tuple[np.ndarray, np.ndarray]:
    lines = data[body:].decode("ascii", errors="replace").splitlines()
    first_line = data[:body].count(b"\n") + 1
    vertices, faces, row = [], [], 0
    for name, count, props in elements:
        columns, at = _ply_columns(path, props) if name in ("vertex", "face") else ([], -1)
        if any(p[0] == "list" for p in props[: max(at, 0)]):
            raise ScenarioError(f"{path}: PLY {name}: list properties before the face list are not supported")
        for _ in range(count):
            while row < len(lines) and not lines[row].strip():
                row += 1
            if row >= len(lines):
                raise ScenarioError(f"{path}: the file ends before its {count} {name} elements")
            words, row = lines[row].split(), row + 1
            try:
                if name == "vertex":
                    vertices.append([float(words[i]) for i in columns])
                elif name == "face":
                    n = int(words[at])
                    polygon = [int(w) for w in words[at + 1 : at + 1 + n]]
                    if len(polygon) != n or n < 3:
                        raise ValueError
                    faces += _fan(polygon)
            except (ValueError, IndexError):
                where = f"{path}: line {first_line + row - 1}"
                raise ScenarioError(f"{where}: bad {name} line {lines[row - 1].strip()!r}") from None
    return np.array(vertices, dtype=float).reshape(-1, 3), np.array(faces, dtype=np.int64).reshape(-1, 3)


def _ply_binary(path: Path, data: bytes, fmt: str, elements, body: int) -> tuple[np.ndarray, np.ndarray]:
    order = "<" if fmt == "binary_little_endian" else ">"
    vertices, faces, offset = np.zeros((0, 3)), [], body
    for name, count, props in elements:
        if any(p[0] == "list" for p in props):
            if name != "face" or len(props) != 1:
                raise ScenarioError(f"{path}: binary PLY: only a face element with one list property is supported")
            count_type, index_type = (np.dtype(order + _PLY_TYPES[t]) for t in props[0][1:3])
            for _ in range(count):
                n = int(np.frombuffer(data, count_type, 1, offset)[0])
                offset += count_type.itemsize
                faces += _fan(np.frombuffer(data, index_type, n, offset).tolist())
                offset += n * index_type.itemsize
            continue
        record = np.dtype([(f"p{i}", order + _PLY_TYPES[p[0]]) for i, p in enumerate(props)])
        table = np.frombuffer(data, record, count, offset)
        offset += count * record.itemsize
        if name == "vertex":
            columns = _ply_columns(path, props)[0]
            vertices = np.stack([table[f"p{i}"].astype(float) for i in columns], axis=1)
    return vertices, np.array(faces, dtype=np.int64).reshape(-1, 3)


def _read_ply(path: Path, data: bytes) -> tuple[np.ndarray, np.ndarray]:
    fmt, elements, body = _ply_header(path, data)
    if fmt == "ascii":
        return _ply_ascii(path, data, elements, body)
    try:
        return _ply_binary(path, data, fmt, elements, body)
    except ValueError:  # np.frombuffer past the end
        raise ScenarioError(f"{path}: the binary PLY body is shorter than its header says") from None


def mesh_arrays(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (V, 3) m, faces (F, 3) 0-based, F >= 1) of an .obj, .stl or .ply file, each line checked; the
    shape's own checks: :func:`solver.collision.read_mesh`."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".obj", ".stl", ".ply"):
        raise ScenarioError(f"{path}: unknown mesh file type {path.suffix!r}; expected .obj, .stl or .ply")
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise ScenarioError(f"{path}: cannot read the mesh file ({exc.strerror or exc})") from None
    if suffix == ".obj":
        vertices, faces, vertex_lines, face_lines = _read_obj(path, data.decode("utf-8", errors="replace"))
        if len(faces):
            _obj_lines_check(path, vertices, faces, vertex_lines, face_lines)
    elif suffix == ".stl":
        vertices, faces = _read_stl(path, data)
    else:
        vertices, faces = _read_ply(path, data)
    if len(faces) == 0:
        raise ScenarioError(f"{path}: no faces in the mesh file")
    return vertices, faces


def obj_text(vertices: np.ndarray, faces: np.ndarray, comment: str = "") -> str:
    """OBJ text of vertices (V, 3) m and faces (F, 3) 0-based (1-based in the file), after a ``# comment`` line."""
    lines = [f"# {comment}"] if comment else []
    lines += [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in np.asarray(vertices, dtype=float)]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in np.asarray(faces, dtype=np.int64)]
    return "\n".join(lines) + "\n"


def write_obj(path: str | Path, vertices: np.ndarray, faces: np.ndarray) -> None:
    """Write vertices (V, 3) m and faces (F, 3) 0-based as an OBJ file (1-based indices)."""
    Path(path).write_text(obj_text(vertices, faces), encoding="utf-8")
