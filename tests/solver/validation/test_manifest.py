"""The manifest against its excerpts (no solving, well under a second): every key frame and the frames kept around
it are in its subject's excerpt and continuous with it, the source frames are consistent, raised heels are marked,
and the coverage the docs quote (subjects, splits, task kinds) is what the manifest holds."""

from __future__ import annotations

import numpy as np
import pytest

from solver.validation.bvh import read_bvh
from solver.validation.harness import MANIFEST, read_manifest
from solver.validation.skeleton import cmu_points

TOP, SUBJECTS, FRAMES = read_manifest()
RAW = {k["name"]: k for k in TOP["keyframes"]}
EXCERPTS = {sid: read_bvh(MANIFEST.parent / s["file"]) for sid, s in SUBJECTS.items()}
STEP = 0.05  # m per frame of trial time between a key frame and a frame around it: a hand moves < 6 m/s


def test_every_key_frame_is_in_its_excerpt_and_not_the_reference() -> None:
    for k in FRAMES:
        n = EXCERPTS[k.subject].frames.shape[0]
        assert 1 <= k.frame < n, k.name
        assert all(1 <= f < n and f != k.frame for f in k.around), k.name


@pytest.mark.parametrize("k", [k for k in FRAMES if k.around], ids=lambda k: k.name)
def test_the_frames_around_are_continuous_with_the_key_frame(k) -> None:
    bvh = EXCERPTS[k.subject]
    key = cmu_points(bvh, k.frame)
    sources = RAW[k.name]["around_source"]
    assert len(sources) == len(k.around)
    assert min(sources) < k.source_frame < max(sources)  # frames before and after, in trial order
    for f, source in zip(k.around, sources, strict=True):
        other = cmu_points(bvh, f)
        moved = max(float(np.linalg.norm(other[n] - key[n])) for n in key)
        assert 0.0 < moved < STEP * abs(source - k.source_frame), (k.name, f, moved)


def test_the_frames_around_each_new_key_frame_are_kept() -> None:
    kept = [k.name for k in FRAMES if k.around]
    assert len(kept) >= 4
    assert all(k.around for k in FRAMES if k.subject in ("80", "143", "69", "15"))


def test_raised_heels_are_marked_where_the_description_says_so() -> None:
    for k in FRAMES:
        if "heel raised" in k.description:
            assert k.heel_raised, k.name
    assert {k.name for k in FRAMES if k.heel_raised} >= {"111_18_pick_descend", "13_24_sweep"}


def test_coverage() -> None:
    held_out = {s for s, e in SUBJECTS.items() if e["split"] == "held-out"}
    assert {s for s, e in SUBJECTS.items() if e["split"] == "train"} == {"115", "137"}  # the weights' subjects
    assert len(held_out) >= 7 and len(FRAMES) >= 32  # issue 35 asks for at least 30 key frames
    kinds = {k.task for k in FRAMES if k.subject in held_out}
    assert {"low_pick", "hold_front", "reach_up", "reach_forward", "set_down"} <= kinds

    def held_out_subjects(task: str) -> set[str]:
        return {k.subject for k in FRAMES if k.subject in held_out and k.task == task}

    assert held_out_subjects("low_pick") >= {"111", "143", "69"}  # the docs: three held-out low-pick subjects
    assert held_out_subjects("set_down") >= {"80", "69"}  # a counter-height and a low set-down
    assert len([k for k in FRAMES if k.task == "reach_forward"]) >= 4  # 80_27, 69_74 (two leans), 15_07
    assert len([k for k in FRAMES if k.task == "hold_front"]) >= 9
