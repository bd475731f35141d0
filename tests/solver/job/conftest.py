"""The example job run once (its motion solved, ~2 s) and short result files cut from that motion."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from solver.job import run_job

REPO = Path(__file__).resolve().parents[3]
EXAMPLE = REPO / "presets" / "jobs" / "box_lift_job.toml"


@pytest.fixture(scope="package")
def example(tmp_path_factory: pytest.TempPathFactory) -> tuple[dict, Path]:
    """The example job's report and its output folder."""
    out = tmp_path_factory.mktemp("job_example")
    return run_job(EXAMPLE, out), out


@pytest.fixture(scope="package")
def short_result(example: tuple[dict, Path], tmp_path_factory: pytest.TempPathFactory):
    """A function: the example's motion cut to the given frame numbers, as a result file; its path."""
    data = json.loads((example[1] / "motion.json").read_text())
    folder = tmp_path_factory.mktemp("short")

    def cut(numbers: list[int]) -> Path:
        path = folder / f"motion_{'_'.join(map(str, numbers))}.json"
        frames = [f for f in data["frames"] if f["frame"] in numbers]
        path.write_text(json.dumps({"scenario": data["scenario"], "frames": frames}))
        return path

    return cut


@pytest.fixture
def write_job():
    """A function: a job file in ``folder`` on the result file ``result`` (work values overridable); its path."""

    def write(folder: Path, result: Path | str, **work) -> Path:
        values = dict(cycle_time=30.0, repetitions=800, shift=8.0) | work
        body = "\n".join(f"{k} = {v!r}" for k, v in values.items())
        path = folder / "job.toml"
        path.write_text(f'name = "t"\n[motion]\nresult = "{result}"\nfps = 24\n[work]\n{body}\n[load]\nmass = 10.0\n')
        return path

    return write
