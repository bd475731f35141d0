"""Files that a writer taking a path writes (Blender's exporters, Save As): put in place as every output of ours is.

:func:`written_by_path` hands the writer a temporary file beside the output (:class:`solver.io.files.OutputFile`
makes it and renames it onto the output), checks what the writer left there (:func:`problem`: the format's header
and end, cheap to read) and only then renames it; a full disk, a writer's error or a failed check is one
ManikinError naming the output, which keeps its old content, and no temporary file is left. Plain Python (no bpy).
"""

from __future__ import annotations

import json
import os
import re
import stat
import struct
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from pathlib import Path
from urllib.parse import quote, unquote

from ...solver.errors import ManikinError
from ...solver.io.files import OutputFile

FBX_HEAD = b"Kaydara FBX Binary  \x00"
FBX_END = bytes.fromhex("f85a8c6adef5d97eece90ce3758f290b")  # the last 16 bytes of every binary FBX
PNG_HEAD, PNG_END = b"\x89PNG\r\n\x1a\n", b"IEND\xaeB`\x82"
ZSTD_HEAD, ZSTD_SEEKABLE_END = b"\x28\xb5\x2f\xfd", b"\xb1\xea\x92\x8f"  # a compressed .blend (Blender 5 default)
_ERRNO = re.compile(r"\[Errno \d+\] ([^\n'\"]+)")
_RAISED = re.compile(r"\w+(Error|Exception): ")  # a traceback's last line


class WriteError(ManikinError):
    """An output that could not be written: its one line says all (``complete``: :func:`.quiet.quietly` adds no
    tail of Blender's console output, which would only repeat the writer's traceback)."""

    complete = True


def reason(error: BaseException | str) -> str:
    """One line for a writer's failure: the system's reason when an OSError is in it ("No space left on device"),
    else the exception line of a Python traceback in it, else its first line (Blender's "Error: " dropped)."""
    if isinstance(error, OSError) and error.strerror:
        return error.strerror
    text = str(error)
    found = _ERRNO.search(text)
    if found:
        return found.group(1).strip()
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    raised = [line for line in lines if _RAISED.match(line)]
    return (raised[-1] if raised else lines[0].removeprefix("Error: ")) if lines else type(error).__name__


def _tail(path: Path, size: int) -> bytes:
    with open(path, "rb") as fh:
        fh.seek(max(0, os.fstat(fh.fileno()).st_size - size))
        return fh.read()


def _bvh(path: Path) -> str | None:
    """A BVH's motion rows counted against its ``Frames:`` line (read in chunks: a long motion's BVH is large)."""
    with open(path, "rb") as fh:
        head = fh.read(1 << 20)  # the hierarchy and the motion's header lines
        frames = re.search(rb"Frames:\s*(\d+)\s*\nFrame Time:[^\n]*\n", head)
        if not head.startswith(b"HIERARCHY") or frames is None:
            return "no BVH header" if not head.startswith(b"HIERARCHY") else "the BVH's motion is cut short"
        fh.seek(frames.end())
        rows, last = 0, b"\n"
        while chunk := fh.read(1 << 20):
            rows, last = rows + chunk.count(b"\n"), chunk[-1:]
    if rows != int(frames.group(1)) or last != b"\n":
        return "the BVH's motion is cut short"
    return None


def _gltf(path: Path) -> str | None:
    """A .gltf's JSON, and each buffer file beside it as long as the JSON says."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, ValueError):
        return "not glTF JSON (cut short?)"
    for buffer in data.get("buffers", []):
        uri = buffer.get("uri", "")
        if uri and not uri.startswith("data:"):
            side = path.parent / unquote(uri)
            if not side.is_file() or side.stat().st_size != buffer.get("byteLength"):
                return "its .bin (the buffer beside it) is missing or cut short"
    return None


def problem(path: Path, kind: str) -> str | None:
    """What is wrong with the file at ``path`` written as a ``kind`` (".fbx", ".bvh", ".glb", ".gltf", ".blend",
    ".png"), or None: empty, or the format's header or end missing (a file cut short)."""
    size = path.stat().st_size
    if size == 0:
        return "the file is empty"
    with open(path, "rb") as fh:
        head = fh.read(32)
    end = _tail(path, 32)
    if kind == ".fbx":
        ok = head.startswith(FBX_HEAD) and end.endswith(FBX_END)
    elif kind == ".glb":
        ok = head[:4] == b"glTF" and len(head) >= 12 and struct.unpack("<I", head[8:12])[0] == size
    elif kind == ".png":
        ok = head.startswith(PNG_HEAD) and end.endswith(PNG_END)
    elif kind == ".blend":
        ok = (head.startswith(b"BLENDER") and b"ENDB" in end) or (
            head.startswith(ZSTD_HEAD) and end.endswith(ZSTD_SEEKABLE_END)
        )
    elif kind == ".bvh":
        return _bvh(path)
    elif kind == ".gltf":
        return _gltf(path)
    else:
        ok = True
    return None if ok else f"the {kind[1:].upper()} file is cut short or malformed"


@contextmanager
def written_by_path(path: str | Path, added: str = "") -> Iterator[Path]:
    """The path a writer that takes one should write ``path`` to (``added``: the suffix that writer puts on any
    name not ending in it, as the glTF exporter does); when the block ends the file is checked and renamed onto
    ``path`` (a .gltf with its .bin). An OSError or RuntimeError (a Blender operator's error) in the block, or a
    failed check: ManikinError naming ``path``; the old file stays and no temporary file is left."""
    path = Path(path)
    out = OutputFile(path, binary=True)
    out.stream.close()  # the writer opens the file by its name
    target = out.temporary or path  # a device is written where it is, unchecked
    work = Path(str(target) + added)
    side: list[OutputFile] = []  # a .gltf's .bin, put in place with it
    leftovers = {work, work.with_suffix(".bin")} - {target} if out.temporary else set()  # a failed writer's files
    try:
        mode = None
        if out.temporary:  # the writer makes the file: Blender's Save As would keep an existing one as NAME1
            mode = stat.S_IMODE(os.stat(target).st_mode)  # the output's (the old file's) permissions
            os.unlink(target)
        try:
            yield work
        except (OSError, RuntimeError) as exc:
            raise WriteError(f"{path}: cannot write ({reason(exc)})") from None
        if not work.is_file():
            raise WriteError(f"{path}: cannot write (nothing was written)")
        if mode is not None:
            os.chmod(work, mode)
        if work != target:  # the writer named it: onto the temporary file's name
            os.replace(work, target)
        wrong = problem(target, path.suffix.lower()) if out.temporary else None
        if wrong is not None:
            raise WriteError(f"{path}: cannot write ({wrong})")
        if path.suffix.lower() == ".gltf" and out.temporary:
            side.append(_bin_beside(path, target, work))
        for extra in side:
            extra.commit()
        out.commit()
    except OSError as exc:
        raise WriteError(f"{path}: cannot write ({reason(exc)})") from None
    finally:
        for extra in side:
            extra.discard()
        out.discard()
        for left in leftovers:
            with suppress(OSError):
                left.unlink()


def _bin_beside(path: Path, target: Path, work: Path) -> OutputFile:
    """The .bin the glTF exporter wrote beside ``work``: moved to a temporary file of ``path``'s .bin, and the
    .gltf at ``target`` made to name the .bin's final name (a .gltf without a .bin: nothing moved)."""
    written = work.with_suffix(".bin")
    out = OutputFile(path.with_suffix(".bin"), binary=True)
    out.stream.close()
    if written.is_file() and out.temporary is not None:
        os.chmod(written, stat.S_IMODE(os.stat(out.temporary).st_mode))  # the old .bin's permissions
        os.replace(written, out.temporary)
        text = target.read_text(encoding="utf-8")
        old, new = json.dumps(quote(written.name)), json.dumps(quote(path.with_suffix(".bin").name))
        with open(target, "w", encoding="utf-8") as fh:
            fh.write(text.replace(old, new))
    return out
