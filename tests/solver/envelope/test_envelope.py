"""Balanced reach envelopes: the direction sphere and the envelope meshes are closed and outward, every balanced
reach is a pose that holds in balance and never beyond the reach without balance, a heavy load in the hand shortens
the forward reach, the OBJ and GLB files parse back (buffer lengths, accessor counts), the command line writes one
set of files per family member and refuses bad input with exit 2 and one line, and importing the package for the
Blender layer loads neither scipy nor matplotlib."""

from __future__ import annotations

import csv
import json
import os
import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from solver import load_preset, solve
from solver.cli.main import main
from solver.envelope import (
    comparison,
    direction_sphere,
    glb_bytes,
    obj_text,
    reach_row,
    read_envelope,
    search_ray,
    sweep_envelope,
)
from solver.envelope.analysis import envelope_file, mesh, section, volume
from solver.envelope.reach import reach_setup
from solver.errors import ResultFileError

REPO = Path(__file__).resolve().parents[3]
TOLERANCE = 0.02  # m: the sweep's reach resolution


def edge_counts(faces: np.ndarray) -> tuple[set, list]:
    """(the directed edges, each directed edge as often as it occurs)."""
    edges = [(int(f[k]), int(f[(k + 1) % 3])) for f in faces for k in range(3)]
    return set(edges), edges


def assert_closed(faces: np.ndarray) -> None:
    """Every edge is shared by exactly two faces, which run along it in opposite directions (consistent)."""
    directed, edges = edge_counts(faces)
    assert len(directed) == len(edges), "an edge runs the same way in two faces"
    assert all((b, a) in directed for a, b in directed), "an edge belongs to one face only"


@pytest.mark.parametrize("frequency", [1, 2, 3, 4])
@pytest.mark.parametrize("hemisphere", ["all", "front", "lower", "right"])
def test_the_direction_sphere_is_closed_outward_and_has_its_size(frequency, hemisphere):
    sphere = direction_sphere(frequency, hemisphere)
    assert np.allclose(np.linalg.norm(sphere.directions, axis=1), 1.0)
    if hemisphere == "all":
        assert len(sphere.directions) == 10 * frequency**2 + 2 and len(sphere.faces) == 20 * frequency**2
    assert_closed(sphere.faces)
    vertices = sphere.vertices(np.ones(len(sphere.directions)))
    full = 4.0 / 3.0 * np.pi * (1.0 if hemisphere == "all" else 0.5)
    assert 0.45 * full < volume(vertices, sphere.faces) <= full  # outward: positive, inside the unit ball


@pytest.fixture(scope="module")
def envelope():
    """The right hand's envelope of male_50 over the 12 directions of an icosahedron."""
    return sweep_envelope(load_preset("male_50"), direction_sphere(1), "right", tolerance=TOLERANCE)


def test_every_direction_is_reached_and_balance_never_reaches_farther(envelope):
    assert np.all(envelope.balanced > 0.3)
    assert np.all(envelope.balanced <= envelope.kinematic + TOLERANCE)
    assert envelope.balanced.mean() < envelope.kinematic.mean() - 0.05  # balance costs reach somewhere
    stats = comparison(envelope)
    assert stats["volume_m3"]["balanced"] < stats["volume_m3"]["kinematic"]
    assert stats["overall"]["mean_difference_m"] == pytest.approx(np.mean(envelope.kinematic - envelope.balanced))


def test_each_balanced_reach_is_a_pose_that_holds_in_balance(envelope):
    """Solved again independently (all constraints, comfort on) from the sweep's pose: met, balance held."""
    model = load_preset("male_50")
    setup = reach_setup(model, "right")
    for i in (0, 5, 9):
        point = envelope.points("balanced")[i]
        result = solve(setup.problem(point), np.array(envelope.poses["balanced"][i]))
        assert result.converged and not result.broken, result.verdict()
        hand = result.state.kin.tcp_frame(model.tcp("hand_r"))[1]
        assert np.linalg.norm(hand - point) < 2e-3
        assert abs(sum(c["force"][2] for c in result.contacts) - model.total_mass * 9.81) < 1.0


def test_the_envelope_meshes_are_closed_and_their_sections_are_loops(envelope):
    for which in ("balanced", "kinematic"):
        m = mesh(envelope, which)
        assert_closed(m.faces)
        assert volume(m.vertices, m.faces) > 0.5
        cut = section(m.vertices, m.faces, envelope.shoulder, np.array([1.0, 0.0, 0.0]))
        assert len(cut) >= 4 and np.allclose(cut[:, :, 0], envelope.shoulder[0])
        ends = [tuple(np.round(p, 9)) for p in cut.reshape(-1, 3)]
        assert all(ends.count(p) == 2 for p in ends)  # every end meets one other segment: a closed loop


def test_a_heavy_load_in_the_hand_shortens_the_forward_reach_in_balance_only():
    ahead_low = (0.0, -1.0, -0.5)
    free, loaded = (reach_row("male_50", ahead_low, load_kg=kg) for kg in (0.0, 20.0))
    assert free["reached"] and loaded["reached"]
    assert loaded["reach_m"] < free["reach_m"] - 0.1
    unbalanced = reach_row("male_50", ahead_low, load_kg=20.0, balance=False)
    assert unbalanced["reach_m"] > free["reach_m"] + 0.1  # without balance the load changes nothing
    assert free["hand_y"] < free["shoulder_y"] - 0.5 and json.dumps(free)  # a plain row


@pytest.mark.parametrize("known", [False, True])
def test_the_reach_is_a_tested_radius_half_a_tolerance_inside_the_nearest_one_not_reached(monkeypatch, known):
    """Right at the edge a test's verdict (and a solve with comfort there) hangs on the last bits of the arithmetic:
    the answer is a radius found reached MARGIN x tolerance short of the nearest one found unreached beyond it, and
    within the tolerance of it; a known seed (the stepping search's planted reach) is never undercut."""
    from solver.envelope import reach

    tests, call = [], reach._Tester.__call__

    def recorded(self, radius, *args):
        tests.append((radius, call(self, radius, *args)))
        return tests[-1][1]

    monkeypatch.setattr(reach._Tester, "__call__", recorded)
    model = load_preset("male_50")
    ahead = np.array([0.0, -1.0, 0.0])
    seed = search_ray(reach_setup(model, "right"), ahead, 0.5) if known else None
    setup = reach_setup(model, "right", feet="step" if known else "planted")
    tests.clear()
    ray = search_ray(setup, ahead, *((seed.radius, seed.pose, True) if known else (0.5,)), tolerance=TOLERANCE)
    unreached = min(r for r, pose in tests if pose is None and r > ray.radius)
    assert unreached - TOLERANCE - 1e-9 <= ray.radius <= unreached - reach.MARGIN * TOLERANCE + 1e-9
    assert any(r == ray.radius and pose is not None for r, pose in tests) or (known and ray.radius == seed.radius)
    assert not known or ray.radius >= seed.radius


def test_a_fixed_hand_orientation_is_held_at_the_reach_and_reaches_no_farther_than_a_free_one():
    model = load_preset("male_50")
    palm_down = np.column_stack([(0.0, -1.0, 0.0), (-1.0, 0.0, 0.0), (0.0, 0.0, -1.0)])  # fingers ahead
    out_right = np.array([-1.0, 0.0, 0.0])
    free = search_ray(reach_setup(model, "right"), out_right, 0.5)
    fixed = search_ray(reach_setup(model, "right", rotation=palm_down), out_right, 0.5)
    assert fixed.reached and fixed.radius <= free.radius + TOLERANCE
    rotation, _ = model.forward(fixed.pose).tcp_frame(model.tcp("hand_r"))
    assert np.degrees(np.arccos(np.clip((np.trace(rotation.T @ palm_down) - 1) / 2, -1, 1))) < 0.5
    row = reach_row("male_50", out_right, rotation=(0.0, 0.70710678, -0.70710678, 0.0))  # the same, as w, x, y, z
    assert row["orientation"] == "0 0.707107 -0.707107 0" and abs(row["reach_m"] - fixed.radius) <= TOLERANCE


def test_keeping_the_centre_of_pressure_off_the_sole_edges_shortens_the_reach():
    ahead = (0.0, -1.0, 0.0)
    whole, inner = (reach_row("male_50", ahead, sole_scale=scale) for scale in (1.0, 0.5))
    assert inner["reached"] and inner["reach_m"] < whole["reach_m"] - 0.05


def parse_glb(data: bytes) -> tuple[dict, bytes]:
    """The JSON and the binary chunk of a GLB, its framing checked."""
    magic, version, length = struct.unpack_from("<III", data, 0)
    assert (magic, version, length) == (0x46546C67, 2, len(data))
    json_length, json_kind = struct.unpack_from("<II", data, 12)
    assert json_kind == 0x4E4F534A and json_length % 4 == 0
    gltf = json.loads(data[20 : 20 + json_length])
    bin_length, bin_kind = struct.unpack_from("<II", data, 20 + json_length)
    assert bin_kind == 0x004E4942 and 28 + json_length + bin_length == len(data)
    return gltf, data[28 + json_length :]


def test_the_glb_parses_back_with_consistent_buffers_and_accessors(envelope, tmp_path):
    meshes = envelope_file(envelope)
    gltf, blob = parse_glb(glb_bytes(meshes))
    assert gltf["asset"]["version"] == "2.0" and gltf["buffers"] == [{"byteLength": len(blob)}]
    for view in gltf["bufferViews"]:
        assert view["byteOffset"] % 4 == 0 and view["byteOffset"] + view["byteLength"] <= len(blob)
    assert [m["name"] for m in gltf["meshes"]] == ["balanced", "kinematic"]
    for node, written in zip(gltf["nodes"], meshes.meshes, strict=True):
        primitive = gltf["meshes"][node["mesh"]]["primitives"][0]
        position = gltf["accessors"][primitive["attributes"]["POSITION"]]
        indices = gltf["accessors"][primitive["indices"]]
        assert position["count"] == len(written.vertices) and indices["count"] == 3 * len(written.faces)
        view = gltf["bufferViews"][position["bufferView"]]
        points = np.frombuffer(blob, "<f4", 3 * position["count"], view["byteOffset"]).reshape(-1, 3)
        assert np.allclose(points.min(axis=0), position["min"]) and np.allclose(points.max(axis=0), position["max"])
        up = points + node["translation"]  # glTF is y up: (x, y, z) of the manikin is (x, z, -y)
        assert np.allclose(up[:, 1], written.vertices[:, 2], atol=1e-5)
        assert np.allclose(up[:, 2], -written.vertices[:, 1], atol=1e-5)
    path = tmp_path / "e.glb"
    path.write_bytes(glb_bytes(meshes))
    back = read_envelope(path)
    assert np.allclose(back.shoulder, envelope.shoulder) and back.info["manikin"] == "male_50"
    for got, written in zip(back.meshes, meshes.meshes, strict=True):
        assert got.name == written.name and np.array_equal(got.faces, written.faces)
        assert np.allclose(got.vertices, written.vertices, atol=1e-5)


def test_the_obj_parses_back(envelope, tmp_path):
    meshes = envelope_file(envelope)
    path = tmp_path / "e.obj"
    path.write_text(obj_text(meshes), encoding="utf-8")
    back = read_envelope(path)
    assert [m.name for m in back.meshes] == ["balanced", "kinematic"] and back.info["hand"] == "right"
    for got, written in zip(back.meshes, meshes.meshes, strict=True):
        assert np.array_equal(got.faces, written.faces) and np.allclose(got.vertices, written.vertices, atol=1e-6)
    (tmp_path / "bad.glb").write_bytes(b"glTF" + bytes(20))
    with pytest.raises(ResultFileError, match="bad.glb: not a readable envelope file"):
        read_envelope(tmp_path / "bad.glb")


def test_a_mesh_file_manikin_did_not_write_is_not_an_envelope(envelope, tmp_path):
    """Any OBJ or glTF parses as meshes; only the ones the envelope writer marked are envelopes (one line)."""
    text = obj_text(envelope_file(envelope))
    (tmp_path / "cube.obj").write_text("# Blender 4.2\n" + text.split("\n", 1)[1], encoding="utf-8")
    data = glb_bytes(envelope_file(envelope)).replace(b'"generator":"Manikin', b'"generator":"Blender')
    (tmp_path / "cube.glb").write_bytes(data)
    for name in ("cube.obj", "cube.glb"):
        with pytest.raises(ResultFileError, match=f"{name}: not a reach envelope written by Manikin") as caught:
            read_envelope(tmp_path / name)
        assert "\n" not in str(caught.value)


def run_cli(*args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(REPO))
    return subprocess.run([sys.executable, "-m", "solver", *args], cwd=REPO, env=env, capture_output=True,
                          text=True, timeout=120)  # fmt: skip


@pytest.mark.slow  # an envelope per member of a family, in worker processes: ~5 s
def test_the_command_writes_one_envelope_per_family_member(tmp_path):
    family = tmp_path / "family"
    assert run_cli("family", "--sex", "female", "--points", "0", "-o", str(family), "-q").returncode == 0
    out = tmp_path / "out"
    done = run_cli("envelope", "--family", str(family), "--frequency", "1", "--hemisphere", "front", "--load", "10",
                   "--hand", "both", "--processes", "2", "-o", str(out), "-q")  # fmt: skip
    assert done.returncode == 0, done.stderr
    names = sorted(p.name for p in out.iterdir())
    stem = "female_mean_right"
    per_hand = [f"female_mean_{hand}.{ext}" for hand in ("left", "right") for ext in ("csv", "glb", "obj", "png")]
    assert names == ["envelopes.csv", *per_hand]
    rows = list(csv.DictReader((out / f"{stem}.csv").open(encoding="utf-8")))
    assert len(rows) == len(direction_sphere(1, "front").directions)
    assert all(float(r["reach_balanced_m"]) <= float(r["reach_kinematic_m"]) + TOLERANCE for r in rows)
    summary = list(csv.DictReader((out / "envelopes.csv").open(encoding="utf-8")))
    assert sorted(row["hand"] for row in summary) == ["left", "right"]
    assert all(row["manikin"] == "female_mean" and float(row["load_kg"]) == 10.0 for row in summary)
    assert_closed(read_envelope(out / f"{stem}.glb").meshes[0].faces)


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (["nobody"], "unknown manikin preset 'nobody'"),
        (["--frequency", "0"], "--frequency: expected a whole number 1..12, got 0"),
        (["--load", "-1"], "--load: expected kg in [0, 100], got -1.0"),
        (["--rotation", "1,2"], "--rotation: expected 4 finite numbers w,x,y,z"),
        (["--tolerance", "0"], "--tolerance: expected m in [0.001, 0.2], got 0.0"),
        (["snake"], "manikin snake: a reach envelope needs the TCPs hand_r, shoulder_r, foot_l, foot_r"),
        (["--family", "nowhere"], "nowhere/family.toml: not found"),
        (["--sole-scale", "0"], "--sole-scale: expected a fraction in [0.1, 1], got 0.0"),
        (["--processes", "0"], "--processes: expected a whole number >= 1, got 0"),
        (["--hemisphere", "inside"], "argument --hemisphere: invalid choice: 'inside'"),
        (["--feet", "hop"], "argument --feet: invalid choice: 'hop'"),
    ],
)
def test_bad_input_exits_2_with_one_line_before_any_work(args, expected, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["envelope", *args, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("error: ") and expected in err
    assert not out.exists()


def test_a_folder_that_holds_files_is_refused(tmp_path, capsys):
    (tmp_path / "keep.txt").write_text("mine", encoding="utf-8")
    assert main(["envelope", "--frequency", "1", "-o", str(tmp_path)]) == 2
    assert "the folder is not empty" in capsys.readouterr().err
    assert [p.name for p in tmp_path.iterdir()] == ["keep.txt"]


def test_the_blender_side_of_the_package_loads_neither_scipy_nor_matplotlib():
    code = ("import sys, solver.envelope, solver.envelope.mesh_files; solver.envelope.read_envelope; "
            "print(sorted(m for m in sys.modules if m.startswith(('scipy', 'matplotlib'))))")  # fmt: skip
    done = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0 and done.stdout.strip() == "[]", done.stderr
