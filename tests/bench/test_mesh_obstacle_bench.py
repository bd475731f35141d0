"""The mesh-obstacle benchmark writes its own section, and its set-up is what it claims: the cabinet within the
margin of the hands in both cases, its rows active only when it presses."""

from bench.mesh_obstacle import run


def test_mesh_obstacle_benchmark_writes_its_section(tmp_path):
    out = tmp_path / "BENCHMARKS.md"
    out.write_text("# Benchmarks\n\nkept text\n", encoding="utf-8")
    run(repeats=1, output=out)
    text = out.read_text(encoding="utf-8")
    assert "kept text" in text and text.count("<!-- mesh-obstacle:start -->") == 1
    assert "a closed box mesh of 10,092 triangles" in text
    parts = {}
    for line in text.splitlines():
        if ": within the 5 cm margin at the end " in line:
            case, rest = line.split(": within the 5 cm margin at the end ")
            within, active = rest.rstrip(".").split("; active ")
            parts[case] = (set(within.split(", ")), set(active.split(", ")))
    assert parts["near"][0] >= {"hand_r", "hand_l"} and parts["near"][1] == {"none"}
    assert parts["pressing"][1] >= {"hand_r", "hand_l"}
    assert "NOT converged" not in text
    for case in ("near", "pressing"):
        rows = [line for line in text.splitlines() if line.startswith(f"| {case} (")]
        assert [row.split(" | ")[1] for row in rows] == ["without", "mesh", "box"]
