"""The README's Python example gives the command line's answer: its code block, run as written on a single-pose and
a motion preset (its scenario path swapped for each, in a scratch folder), writes a result whose frames and joint
values are those of ``python -m solver solve`` on the same file (within 1e-9), so the README cannot drift from the
CLI again. The documentation's page on the solver from Python (docs/guide/python.md) shows the same block.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from solver import kernels, read_result

ROOT = Path(__file__).resolve().parents[1]
SCENARIO_PATH = re.compile(r'"(presets/scenarios/\w+\.toml)"')


def python_blocks(text: str) -> list[str]:
    """The ```python fenced blocks of a Markdown text."""
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.MULTILINE | re.DOTALL)


def readme_example(document: str = "README.md") -> str:
    """The Python example of a Markdown ``document`` (relative to the checkout): its one block that loads a scenario."""
    text = (ROOT / document).read_text(encoding="utf-8")
    blocks = [b for b in python_blocks(text) if "load_scenario" in b]
    assert len(blocks) == 1, f"expected one ```python block with solver.load_scenario in {document}"
    return blocks[0]


def test_the_docs_show_the_readme_example() -> None:
    assert readme_example("docs/guide/python.md") == readme_example()


def cli_result(scenario: Path, folder: Path) -> Path:
    """``python -m solver solve SCENARIO -o folder/cli.json -q``, run from ``folder``; the file it wrote."""
    folder.mkdir()
    out = folder / "cli.json"
    env = dict(os.environ, MANIKIN_KERNELS="auto" if kernels.active() else "numpy")  # the example's kernels
    done = subprocess.run(
        [sys.executable, "-m", "solver", "solve", str(scenario), "-o", str(out), "-q"],
        cwd=ROOT, capture_output=True, text=True, timeout=300, env=env,
    )  # fmt: skip
    assert done.returncode in (0, 3) and out.is_file(), done.stderr
    return out


@pytest.mark.parametrize("preset", ["box_lift.toml", pytest.param("box_lift_motion.toml", marks=pytest.mark.slow)])
def test_the_readme_example_gives_the_cli_answer(preset: str, tmp_path: Path, monkeypatch, capsys) -> None:
    scenario = ROOT / "presets" / "scenarios" / preset
    code = readme_example()
    named = set(SCENARIO_PATH.findall(code))
    assert len(named) == 1, f"the example should load one scenario preset, names {named}"
    work = tmp_path / "readme"
    work.mkdir()
    monkeypatch.chdir(work)
    exec(compile(code.replace(named.pop(), str(scenario)), "README.md", "exec"), {"__name__": "readme"})
    assert capsys.readouterr().out  # it shows something
    written = sorted(work.glob("*.json"))
    assert len(written) == 1, f"the example should write one result JSON, wrote {written}"
    ours, cli = read_result(written[0]).frames, read_result(cli_result(scenario, tmp_path / "cli")).frames
    assert [f.number for f in ours] == [f.number for f in cli] and len(cli) >= 1
    assert len(cli) > 1 or "motion" not in preset
    for mine, theirs in zip(ours, cli, strict=True):
        assert mine.joint_names == theirs.joint_names and mine.converged == theirs.converged
        np.testing.assert_allclose(mine.joint_value, theirs.joint_value, rtol=0, atol=1e-9, err_msg=f"{mine.number}")
