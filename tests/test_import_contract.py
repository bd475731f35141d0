"""The import contract (pyproject.toml ``[tool.importlinter]``), checked by import-linter: ``solver/``'s folders are
layers whose imports only point down, no module reaches itself through a circle of siblings, and neither the solver
nor the extension imports the benchmarks."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_the_import_contract_holds() -> None:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    lint = Path(sys.executable).with_name("lint-imports")
    run = subprocess.run([str(lint), "--no-cache"], cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-2000:]
