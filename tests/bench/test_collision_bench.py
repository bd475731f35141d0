"""The collision benchmark checks its mesh distances against the box primitive and writes its own section."""

import pytest

from bench.collision import body, run


@pytest.mark.slow
def test_collision_benchmark_writes_its_section(tmp_path):
    out = tmp_path / "BENCHMARKS.md"
    out.write_text("# Benchmarks\n\nkept text\n", encoding="utf-8")
    run(repeats=2, output=out)
    text = out.read_text(encoding="utf-8")
    assert "kept text" in text and text.count("<!-- collision-bench:start -->") == 1
    assert "| typical: standing, right hand 1 cm over a cabinet | 2 |" in text
    assert "| worst: lying 2 cm over a bed, all 20 within the margin | 20 |" in text
    assert len(body()[0]) == 20
