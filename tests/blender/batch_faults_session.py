"""A full disk under the batch script's writers, run by tests/blender/test_batch_faults.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/batch_faults_session.py <zip> <out.json> <work dir>

installs the extension zip, bakes frames 1-3 of the snake motion, then writes each output the batch writes (FBX,
BVH, .glb, .gltf, the .blend, the key-pose picture; Export Motion, the UI's operator; ``batch.py --out``) over an
old file in ``<work>/full`` while the disk is full, and records the error, the old file and what else is in the
folder. The disk: a tmpfs the test mounted at ``<work>/full`` is filled with a file; where none could be mounted,
each writer runs under a file-size limit (RLIMIT_FSIZE) instead: the real writers fail either way, with "No space
left on device" or "File too large". Then the filler goes and a .gltf replaces its old .gltf and .bin. The bake
also records what a frame's record keeps once it is handed on (issue 34: a long bake's memory).
"""

from __future__ import annotations

import contextlib
import importlib
import io
import json
import os
import resource
import signal
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from session_tools import error_of, install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
SNAKE = ROOT / "presets" / "scenarios" / "snake_motion.toml"
FULL = WORK / "full"
LIMIT = 2048  # bytes: the file-size limit where no tmpfs could be mounted (every output here is larger)
seen: dict = {"seconds": {}, "cases": {}}
began = time.perf_counter()

import bpy  # noqa: E402

module = install(ZIP)
job = importlib.import_module(module + ".blender_manikin.motion.job")
exports = importlib.import_module(module + ".blender_manikin.motion.exports")
picture = importlib.import_module(module + ".blender_manikin.motion.picture")
bake = importlib.import_module(module + ".blender_manikin.motion.bake")
batch = importlib.import_module(module + ".blender_manikin.batch")
ManikinError = importlib.import_module(module + ".solver.errors").ManikinError
seen["how"] = how = "tmpfs" if os.path.ismount(FULL) else "rlimit"
FULL.mkdir(exist_ok=True)


@contextlib.contextmanager
def full_disk():
    """Writes fail inside: the tmpfs is full already, else a file-size limit (SIGXFSZ ignored: EFBIG instead)."""
    if how == "tmpfs":
        yield
        return
    old = resource.getrlimit(resource.RLIMIT_FSIZE)
    handler = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (LIMIT, old[1]))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, old)
        signal.signal(signal.SIGXFSZ, handler)


def limited(written_by_path):
    """``written_by_path`` with its block (the writer only) under the full disk."""

    @contextlib.contextmanager
    def wrapper(*args, **kwargs):
        with written_by_path(*args, **kwargs) as work, full_disk():
            yield work

    return wrapper


WRITERS = {owner: owner.written_by_path for owner in (job, exports, picture)}
if how == "rlimit":  # only the writers under the limit: Blender's own temporary files (render tiles) stay free
    for owner, written_by_path in WRITERS.items():
        owner.written_by_path = limited(written_by_path)

t0 = time.perf_counter()
arm = job.open_scene(job.Job(scenario=SNAKE))
baker = bake.Baker(bpy.context.scene, arm, 1, 3)
handed: list[int] = []  # each frame's residuals as the files get them
baker.on_frame = lambda record, result: handed.append(len(record.residuals))
baker.run()
seen["residuals_handed_on"] = handed
seen["residuals_kept"] = sum(len(r.residuals) for r in baker.records)  # after: none (a long bake's memory)
seen["record_has_dict"] = hasattr(baker.records[0], "__dict__")
baker.write(thin=True)
seen["seconds"]["bake"] = time.perf_counter() - t0

NAMES = ["m.fbx", "m.bvh", "m.glb", "m.gltf", "m.bin", "m.blend", "m.png", "ui.fbx", "cli.blend"]
for name in NAMES:
    (FULL / name).write_bytes(b"OLD")
if how == "tmpfs":
    fd = os.open(FULL / "filler", os.O_WRONLY | os.O_CREAT)
    try:
        while True:
            os.write(fd, b"\0" * 65536)
    except OSError:
        pass
    os.close(fd)


def attempt(name: str, call) -> None:
    """Run a writer of ``FULL / name``; record its error (one line?) and whether the old file is intact."""
    t = time.perf_counter()
    try:
        call(FULL / name)
        error = None
    except ManikinError as exc:
        error = str(exc)
    seen["cases"][name] = dict(error=error, old=(FULL / name).read_bytes() == b"OLD")
    seen["seconds"][name] = time.perf_counter() - t


for name in ("m.fbx", "m.bvh", "m.glb", "m.gltf"):
    attempt(name, lambda path: job.quietly(exports.export, arm, path, 1, 3))
attempt("m.blend", job.save_blend)
attempt("m.png", lambda path: job.quietly(picture.render_key_poses, arm, [2], path, None, "full", (32, 24), 1))
seen["bin_old"] = (FULL / "m.bin").read_bytes() == b"OLD"

bpy.context.view_layer.objects.active = arm
seen["ui"] = error_of(lambda: bpy.ops.manikin.export_motion(filepath=str(FULL / "ui.fbx")))
seen["ui_old"] = (FULL / "ui.fbx").read_bytes() == b"OLD"
seen["listing_full"] = sorted(os.listdir(FULL))

# the command line: batch.py --out on the full disk (its own scene), exit code and what it printed
stderr = io.StringIO()
t = time.perf_counter()
with contextlib.redirect_stderr(stderr):
    seen["cli_code"] = batch.main(
        ["--scenario", str(SNAKE), "--frames", "1", "2", "-q", "--out", str(FULL / "cli.blend")]
    )
seen["cli_stderr"] = stderr.getvalue()
seen["cli_old"] = (FULL / "cli.blend").read_bytes() == b"OLD"
seen["seconds"]["cli"] = time.perf_counter() - t

# room again: a .gltf replaces its old .gltf and .bin, the .gltf naming the new .bin
with contextlib.suppress(FileNotFoundError):
    (FULL / "filler").unlink()
for owner, written_by_path in WRITERS.items():
    owner.written_by_path = written_by_path
arm = job.find_manikin(None)
exports.export(arm, FULL / "m.gltf", 1, 2)
job.save_blend(FULL / "m.blend")  # over an old file: Blender keeps no "NAME1" copy of anything of ours
seen["blend_size"] = (FULL / "m.blend").stat().st_size
seen["gltf"] = json.loads((FULL / "m.gltf").read_text(encoding="utf-8"))["buffers"]
seen["bin_size"] = (FULL / "m.bin").stat().st_size
seen["listing_after"] = sorted(os.listdir(FULL))

seen["seconds"]["total"] = time.perf_counter() - began
OUT.write_text(json.dumps(seen, indent=1), encoding="utf-8")
exit_process(0)
