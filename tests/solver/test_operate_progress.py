"""``manikin operate`` shows its progress on standard error (Blender's Operations panel reads it from the log): the
progress line of every long run ("frames N/M ..."), none with -q."""

from __future__ import annotations

import solver.progress
from solver.cli.main import main

TINY = """name = "tiny"
[manikin]
preset = "male_50"
[operate]
fps = 4
[[operations]]
do = "reach"
to = [0.2, -0.4, 1.1]
[[operations]]
do = "wait"
duration = 0.5
"""


def test_operate_writes_progress_lines_unless_quiet(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(solver.progress, "LOG_EVERY_S", 0.0)  # a line per frame here: the test needs no long run
    path = tmp_path / "tiny.toml"
    path.write_text(TINY, encoding="utf-8")
    assert main(["operate", str(path), "-o", str(tmp_path / "out")]) in (0, 3)
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.startswith("frames ")]
    assert lines and lines[-1].startswith("frames ") and "/" in lines[-1]
    assert main(["operate", str(path), "-o", str(tmp_path / "quiet"), "-q"]) in (0, 3)
    assert "frames " not in capsys.readouterr().err
