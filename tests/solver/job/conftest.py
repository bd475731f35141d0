"""The example job run once (its motion solved, ~2 s; its report drawn in full, ~2 s), short result files cut from
that motion, and the job of one of its frames run once (its frame pictures left out: :func:`_pictures_left_out`)."""

from __future__ import annotations

import contextlib
import io
import json
from collections.abc import Callable, Iterator
from pathlib import Path
from unittest import mock

import pytest

from solver.cli.main import main
from solver.job import html, run_job

REPO = Path(__file__).resolve().parents[3]
EXAMPLE = REPO / "presets" / "jobs" / "box_lift_job.toml"


@contextlib.contextmanager
def _pictures_left_out(keep: str = "") -> Iterator[None]:
    """Inside, the HTML report leaves out the frame pictures (side and front views, ~0.25 s each) of every method but
    the one titled ``keep``; its tables and plots are drawn. For the runs whose tests read the numbers, tables and
    plots: the example's report draws every picture (test_job_html.py checks them)."""
    draw = html.pictures

    def pictures(title: str, result: dict, frames: dict) -> str:
        return draw(title, result, frames) if title == keep else ""

    with mock.patch.object(html, "pictures", pictures):
        yield


@pytest.fixture(scope="package")
def pictures_left_out() -> Callable[..., contextlib.AbstractContextManager[None]]:
    """A context manager: the HTML report's frame pictures left out inside (:func:`_pictures_left_out`)."""
    return _pictures_left_out


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


def _write_job(folder: Path, result: Path | str, **work) -> Path:
    """A job file in ``folder`` on the result file ``result`` (work values overridable); its path."""
    values = dict(cycle_time=30.0, repetitions=800, shift=8.0) | work
    body = "\n".join(f"{k} = {v!r}" for k, v in values.items())
    path = folder / "job.toml"
    path.write_text(f'name = "t"\n[motion]\nresult = "{result}"\nfps = 24\n[work]\n{body}\n[load]\nmass = 10.0\n')
    return path


@pytest.fixture
def write_job():
    """A function: a job file in ``folder`` on the result file ``result`` (work values overridable); its path."""
    return _write_job


@pytest.fixture(scope="package")
def one_frame(short_result, tmp_path_factory: pytest.TempPathFactory, pictures_left_out) -> tuple[dict, str]:
    """``manikin job`` on the example's frame 30 alone, zero repetitions, a 1 s cycle: job.json and what the command
    printed (the one-frame checks of LiFFT, % capable and EAWS share this run; its one-point plots are drawn, its
    frame pictures left out)."""
    folder = tmp_path_factory.mktemp("one_frame")
    job = _write_job(folder, short_result([30]), cycle_time=1.0, repetitions=0)
    with contextlib.redirect_stdout(io.StringIO()) as printed, pictures_left_out():
        assert main(["job", str(job), "-o", str(folder / "out")]) == 0
    return json.loads((folder / "out" / "job.json").read_text()), printed.getvalue()
