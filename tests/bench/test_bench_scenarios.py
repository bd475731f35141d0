"""The scenario benchmark writes its table (one round here) into its own section of the report."""

from bench.scenarios import SCENARIOS, run_benchmarks


def test_scenario_benchmark_writes_every_case(tmp_path):
    out = tmp_path / "BENCHMARKS.md"
    out.write_text("# Benchmarks\n\nkept text\n", encoding="utf-8")
    run_benchmarks(out, repeats=1)
    text = out.read_text(encoding="utf-8")
    assert "kept text" in text
    assert text.count("<!-- solver-bench:start -->") == 1
    for name in SCENARIOS:
        assert f"| {name} (cold, from its start pose) |" in text
    assert "constraints only |" in text and "1/1 |" in text
