"""A full disk under the batch script's writers (tests/blender/batch_faults_session.py in a subprocess, the built
zip installed): exports (FBX, BVH, .glb, .gltf with its .bin), the .blend of ``--out``, the ``--picture`` and the
UI's Export Motion each fail with one line naming the file, keep the old file and leave no temporary file; the
batch exits 2 as for its other write errors. The disk is a small tmpfs where one can be mounted (root), else a
file-size limit on the writers (the session records which: ``how``). And a baked frame's record keeps no
residuals once the files have them.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

REASONS = {"tmpfs": "No space left on device", "rlimit": "File too large"}
CUT_BLEND = "the BLEND file is cut short or malformed"  # written.py's check: Blender wrote under RLIMIT_FSIZE
# without an error (a .blend cut at the limit), which only the check catches


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    work = tmp_path_factory.mktemp("batch_faults")
    full = work / "full"
    full.mkdir()
    # 8 MB: room for Blender 4.2's uncompressed .blend once the filler is gone (the session fills all of it first)
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=8m", "tmpfs", str(full)], capture_output=True)
    try:
        return run_session(work, "batch_faults_session.py")
    finally:
        if mounted.returncode == 0:
            subprocess.run(["umount", str(full)], check=False)


def test_every_writer_on_a_full_disk_says_so_and_keeps_the_old_file(session: dict) -> None:
    reason = REASONS[session["how"]]
    full = Path(session["work"]) / "full"
    for name, case in session["cases"].items():
        why = (reason, CUT_BLEND) if name.endswith(".blend") else (reason,)  # Blender may not see a size limit
        assert case["error"] in [f"{full / name}: cannot write ({w})" for w in why], (name, case)
        assert case["old"], name
    assert session["bin_old"]  # the .gltf's .bin too


def test_export_motion_and_the_batch_on_a_full_disk_say_one_line_and_leave_no_temporary(session: dict) -> None:
    reason = REASONS[session["how"]]
    full = Path(session["work"]) / "full"
    assert session["ui"].strip() == f"Error: {full / 'ui.fbx'}: cannot write ({reason})" and session["ui_old"]
    assert session["cli_code"] == 2 and session["cli_old"]
    said = session["cli_stderr"]  # under a file-size limit Blender may not notice: the check does
    assert said in (f"error: {full / 'cli.blend'}: cannot write ({why})\n" for why in (reason, CUT_BLEND)), said
    names = ["cli.blend", "m.bin", "m.blend", "m.bvh", "m.fbx", "m.glb", "m.gltf", "m.png", "ui.fbx"]
    assert [n for n in session["listing_full"] if n != "filler"] == names  # no temporary file left
    assert session["listing_after"] == names


def test_a_gltf_replaces_its_old_bin_and_names_it(session: dict) -> None:
    (buffer,) = session["gltf"]
    assert buffer["uri"] == "m.bin" and buffer["byteLength"] == session["bin_size"] > 3
    assert session["blend_size"] > 1000


def test_a_baked_frame_keeps_no_residuals_once_handed_on(session: dict) -> None:
    """The files get each frame's residuals; the bake then keeps a few numbers per frame (issue 34: 10,000 frames
    kept about 25 MB of residual dictionaries), and a record has no dict of its own."""
    assert session["residuals_handed_on"] and all(n > 0 for n in session["residuals_handed_on"])
    assert session["residuals_kept"] == 0 and not session["record_has_dict"]
