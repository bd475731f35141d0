"""The body mesh's fit table in docs/BODY_MESH.md: per landmark, the distance (mm) from the fitted MPFB joint to
our joint centre for the three human presets, with the macros, the mesh's mass and the time ``fit_body`` takes.

    python -m bench.body_fit [--write]    # print the table, or replace it in docs/BODY_MESH.md
"""

from __future__ import annotations

import argparse
import platform
import re
import time
from pathlib import Path

import numpy as np

from solver.bodymesh import fit_body, load_body_data
from solver.io.scenario.bodies import load_preset

DOC = Path(__file__).resolve().parents[2] / "docs" / "BODY_MESH.md"
PRESETS = ("female_5", "male_50", "male_95")
BEGIN, END = "<!-- fit table: python -m bench.body_fit --write -->", "<!-- end of fit table -->"


def table() -> str:
    load_body_data()  # read once, outside the timing
    bodies, seconds = {}, {}
    for name in PRESETS:
        model = load_preset(name)
        runs = []
        for _ in range(3):
            start = time.perf_counter()
            bodies[name] = (model, fit_body(model))
            runs.append(time.perf_counter() - start)
        seconds[name] = float(np.median(runs))
    landmarks = [k for k in bodies[PRESETS[0]][1].fit_error if not k.endswith("_r") and "_r_" not in k]
    lines = ["| landmark (our joint) | " + " | ".join(PRESETS) + " |", "|---" * (len(PRESETS) + 1) + "|"]
    for key in landmarks:
        joint = bodies[PRESETS[0]][1].joint_names[key]
        cells = [f"{1000 * bodies[p][1].fit_error[key]:.1f}" for p in PRESETS]
        lines.append(f"| {key} ({joint}) | " + " | ".join(cells) + " |")
    lines.append("")
    for name in PRESETS:
        model, body = bodies[name]
        m = body.macros
        lines.append(f"- {name}: gender {m.gender:.2f}, height {m.height:.3f}, weight {m.weight:.3f}, muscle "
                     f"{m.muscle:.2f}; mesh {body.mass:.1f} kg for a {model.total_mass:.1f} kg manikin; "
                     f"fit_body {seconds[name]:.2f} s (median of 3)")  # fmt: skip
    lines.append(f"- left side shown (the right is its mirror image); machine: {platform.machine()}, "
                 f"{platform.python_implementation()} {platform.python_version()}")  # fmt: skip
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--write", action="store_true", help=f"replace the table in {DOC.name}")
    args = parser.parse_args(argv)
    text = table()
    if args.write:
        doc = DOC.read_text(encoding="utf-8")
        pattern = re.compile(re.escape(BEGIN) + ".*?" + re.escape(END), re.S)
        DOC.write_text(pattern.sub(lambda _: f"{BEGIN}\n{text}\n{END}", doc), encoding="utf-8")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
