"""Populations and manikin families: the boundary lies on the coverage contour and holds that share of the
population, samples reproduce the model's moments from their seed, every written member loads and solves a
preset pose, the command line writes the files and refuses bad arguments with exit 2 and one line."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import chi2

from solver import load_scenario, solve
from solver.io.scenario.bodies import PRESETS_DIR, load_body
from solver.population import (
    INDEX,
    boundary_points,
    coverage_radius,
    make_family,
    population,
    read_family,
    write_family,
)
from solver.population.ansur2 import STATS

REPO = Path(__file__).resolve().parents[3]
PRESET_FAMILY = PRESETS_DIR / "families" / "ansur2_c95"
SEXES = ("male", "female")


def run_cli(*args: str, cwd: Path = REPO) -> subprocess.CompletedProcess:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    return subprocess.run(
        [sys.executable, "-m", "solver", *args], cwd=cwd, env=env, capture_output=True, text=True, timeout=60
    )


@pytest.mark.parametrize("coverage", [0.5, 0.9, 0.95, 0.99])
def test_coverage_radius_is_the_chi_square_quantile_with_two_degrees_of_freedom(coverage):
    assert coverage_radius(coverage) ** 2 == pytest.approx(chi2.ppf(coverage, 2), rel=1e-12)


@pytest.mark.parametrize("sex", SEXES)
@pytest.mark.parametrize("points", [3, 8, 13])
def test_boundary_points_lie_on_the_coverage_contour(sex, points):
    pop = population(sex)
    size, angles = boundary_points(pop, 0.95, points)
    assert size.shape == (points, 2) and angles[0] == 0.0
    assert np.allclose(pop.mahalanobis(size), coverage_radius(0.95), rtol=1e-12)
    if points == 8:  # axes and diagonals: opposite points are symmetric about the mean, the first is big and heavy
        assert np.allclose(size[:4] + size[4:], 2 * pop.mean)
        assert np.all(size[0] > pop.mean)


@pytest.mark.parametrize("sex", SEXES)
def test_the_population_model_is_the_survey_s(sex):
    pop, stats = population(sex), STATS[sex]
    assert pop.mean == pytest.approx([stats["stature"][0], stats["mass"][0]])
    assert pop.sd == pytest.approx([stats["stature"][1], stats["mass"][1]])
    assert pop.correlation == pytest.approx(stats["r"])
    np.linalg.cholesky(pop.residual_cov)  # the rounded residual correlations still make a covariance
    at_mean = pop.measurements(*pop.mean)
    assert 0.51 < at_mean["sitting_height"] / pop.mean[0] < 0.54  # ANSUR II: 0.523 men, 0.526 women


@pytest.mark.parametrize("sex", SEXES)
def test_samples_converge_to_the_model_and_fill_the_ellipse(sex):
    pop, n = population(sex), 40_000
    size, extra = pop.sample(n, np.random.default_rng(7))
    se = pop.sd / np.sqrt(n)
    assert np.all(np.abs(size.mean(axis=0) - pop.mean) < 4 * se)
    assert np.allclose(np.cov(size.T), pop.cov, rtol=0.05)
    assert np.corrcoef(size.T)[0, 1] == pytest.approx(pop.correlation, abs=0.02)
    design = np.column_stack([np.ones(n), size])
    fitted = np.linalg.lstsq(design, extra, rcond=None)[0].T
    assert np.allclose(fitted[:, 1], pop.regression[:, 1], atol=0.03)  # per m of stature
    assert np.allclose(np.cov((extra - design @ fitted.T).T), pop.residual_cov, rtol=0.1, atol=2e-6)
    inside = np.mean(pop.mahalanobis(size) <= coverage_radius(0.95))
    assert inside == pytest.approx(0.95, abs=0.005)


def test_samples_are_reproducible_from_their_seed():
    one = make_family(("male", "female"), points=0, samples=5, seed=11)
    again = make_family(("female",), points=0, samples=5, seed=11)
    other = make_family(("female",), points=0, samples=5, seed=12)
    women = [m for m in one if m.sex == "female"]
    assert women == again  # a sex's samples do not depend on the other sexes drawn
    assert [m.stature for m in again] != [m.stature for m in other]
    assert [m.role for m in again] == ["mean"] + ["sample"] * 5


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    folder = tmp_path_factory.mktemp("family") / "fam"
    members = make_family(SEXES, coverage=0.9, points=8, samples=2, seed=3)
    info = {"source": "test", "coverage": 0.9, "points": 8, "samples": 2, "seed": 3}
    write_family(members, folder, info)
    return members, folder


def test_a_written_family_reads_back_and_its_boundary_stays_on_the_contour(written):
    members, folder = written
    family = read_family(folder)
    assert family.members == tuple(members)
    assert [f.name for f in family.files] == [f"{m.name}.toml" for m in members]
    for sex in SEXES:
        pop = population(sex)
        boundary = np.array([[m.stature, m.mass] for m in members if m.sex == sex and m.role == "boundary"])
        assert len(boundary) == 8
        assert np.allclose(pop.mahalanobis(boundary), coverage_radius(0.9), atol=2e-3)  # rounded to 0.1 mm, 10 g


def test_every_written_member_loads_with_its_measurements(written):
    members, folder = written
    for member in members:
        body = load_body(file=folder / f"{member.name}.toml")
        assert body.info["stature"] == member.stature and body.info["mass"] == member.mass
        assert body.info["measurements"] == member.measurements
        assert body.mass.sum() == pytest.approx(member.mass)


def test_every_preset_family_member_solves_the_box_lift(tmp_path):
    family = read_family(PRESET_FAMILY)
    assert {m.role for m in family.members} == {"boundary", "mean"} and len(family.members) == 18
    text = (PRESETS_DIR / "scenarios" / "box_lift.toml").read_text()
    assert 'preset = "male_50"' in text
    for member, file in zip(family.members, family.files, strict=True):
        path = tmp_path / f"box_lift_{member.name}.toml"  # [manikin] file = the member's body file
        path.write_text(text.replace('preset = "male_50"', f'file = "{file.resolve().as_posix()}"'))
        scenario = load_scenario(path)
        assert scenario.model.info["stature"] == member.stature
        result = solve(scenario.problem_at(scenario.frames[0]), scenario.start, scenario.options)
        assert result.converged, member.name


def test_the_preset_family_is_what_its_command_writes(tmp_path):
    info = read_family(PRESET_FAMILY).info
    args = info["command"].split()[3:]  # after "python -m solver"
    done = run_cli(*args, "-o", str(tmp_path / "again"), "-q")
    assert done.returncode == 0, done.stderr
    shipped = sorted(p.name for p in PRESET_FAMILY.iterdir())
    assert shipped == sorted(p.name for p in (tmp_path / "again").iterdir())
    for name in shipped:
        assert (PRESET_FAMILY / name).read_text() == (tmp_path / "again" / name).read_text(), name


def test_the_command_writes_a_family_and_presets_lists_it(tmp_path):
    done = run_cli(
        "family", "--sex", "female", "--points", "4", "--samples", "3", "--seed", "5", "-o", str(tmp_path / "f")
    )
    assert done.returncode == 0, done.stderr
    assert "wrote 8 body files (4 boundary, 1 mean, 3 sample)" in done.stdout
    family = read_family(tmp_path / "f")
    assert [m.name for m in family.members][-3:] == ["female_s1", "female_s2", "female_s3"]
    assert family.info["seed"] == 5 and (tmp_path / "f" / INDEX).is_file()
    listed = run_cli("presets")
    assert "families: presets/families/ansur2_c95" in listed.stdout


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--coverage", "1.5"], ["--coverage", "[0.01, 0.9999]", "got 1.5"]),
        (["--coverage", "nan"], ["--coverage", "got nan"]),
        (["--coverage", "most"], ["--coverage", "invalid float value: 'most'"]),
        (["--points", "2"], ["--points", "got 2"]),
        (["--samples", "-4"], ["--samples", "got -4"]),
        (["--seed", "-1"], ["--seed", "got -1"]),
        (["--sex", "any"], ["--sex", "invalid choice: 'any'"]),
        (["-o", "FILE"], ["is a file, expected a new or empty folder"]),
        (["-o", "FULL"], ["the folder is not empty"]),
    ],
)
def test_bad_arguments_exit_2_with_one_line(tmp_path, args, words):
    (tmp_path / "FILE").write_text("keep me")
    (tmp_path / "FULL").mkdir()
    (tmp_path / "FULL" / "mine.txt").write_text("keep me too")
    if "-o" not in args:
        args = [*args, "-o", "out"]
    done = run_cli("family", *args, cwd=tmp_path)
    assert done.returncode == 2
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ")
    for word in words:
        assert word in lines[0]
    assert not (tmp_path / "out").exists()
    assert (tmp_path / "FILE").read_text() == "keep me" and (
        tmp_path / "FULL" / "mine.txt"
    ).read_text() == "keep me too"
