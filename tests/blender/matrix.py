"""The version matrix: the Blender tests once per supported Blender series, each in its Blender-equivalent
environment (environments.py), and the outcome per test and version in docs/COMPATIBILITY.md.

    .venv/bin/python tests/blender/matrix.py [4.2 4.5 5.0]      # from the repository root; exit 1 if any failed

Each leg builds the linux-x64 zip with that version's own build tool, installs it into a throwaway user folder
and runs the whole user flow (tests/blender/*_session.py, batch.py by that environment's Python).
"""

from __future__ import annotations

import datetime
import os
import platform
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from pathlib import Path

from environments import BLENDERS, DEFAULT, ROOT, SELECT, python_of

OUTPUT = ROOT / "docs" / "COMPATIBILITY.md"


def run_leg(series: str, junit: Path) -> tuple[dict[str, str], float]:
    """Run tests/blender for ``series``; {test id: "pass" | "FAIL" | "skip"} and the seconds it took."""
    python_of(series)  # create the environment before the clock starts
    env = dict(os.environ, **{SELECT: series})
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", f"--junitxml={junit}",
                    "tests/blender"], cwd=ROOT, env=env)  # fmt: skip
    seconds = time.perf_counter() - t0
    outcomes = {}
    for case in ET.parse(junit).iter("testcase"):
        name = f"{case.get('classname', '').rsplit('.', 1)[-1]}::{case.get('name')}"
        failed = case.find("failure") is not None or case.find("error") is not None
        outcomes[name] = "FAIL" if failed else ("skip" if case.find("skipped") is not None else "pass")
    return outcomes, seconds


def table(legs: dict[str, tuple[dict[str, str], float]]) -> str:
    series = list(legs)
    names = sorted({name for outcomes, _ in legs.values() for name in outcomes})
    head = "| test | " + " | ".join(f"Blender {s} (bpy {BLENDERS[s][0]}, numpy {BLENDERS[s][1]})" for s in series)
    lines = [head + " |", "|---|" + "---|" * len(series)]
    for name in names:
        lines.append(f"| `{name}` | " + " | ".join(legs[s][0].get(name, "-") for s in series) + " |")
    passed = {s: sum(v == "pass" for v in legs[s][0].values()) for s in series}
    totals = [f"{passed[s]}/{len(legs[s][0])} in {legs[s][1]:.0f} s" for s in series]
    lines.append("| **passed** | " + " | ".join(totals) + " |")
    return "\n".join(lines)


def main(argv: list[str]) -> int:
    chosen = argv or list(BLENDERS)
    unknown = [s for s in chosen if s not in BLENDERS]
    if unknown:
        print(f"error: unknown Blender series {unknown[0]} (known: {', '.join(BLENDERS)})", file=sys.stderr)
        return 2
    legs = {}
    with tempfile.TemporaryDirectory(prefix="manikin-matrix-") as tmp:
        for series in chosen:
            legs[series] = run_leg(series, Path(tmp) / f"{series}.xml")
    failed = [s for s, (outcomes, _) in legs.items() if not outcomes or "FAIL" in outcomes.values()]
    today = datetime.date.today().isoformat()
    text = f"""# Compatibility

The extension as a user meets it, per supported Blender series: `.venv/bin/python tests/blender/matrix.py`
runs `tests/blender` once per series in a virtual environment holding only that `bpy` wheel and the numpy that
Blender release bundles (no scipy, no matplotlib, no numba: the extension's own wheels must bring them). Each leg builds
the linux-x64 zip with that version's build tool, installs it into a throwaway user folder and drives the
whole user flow: every preset, targets, loops, loads, solve, undo, reset, live mode, scenario export and
import, a keyed scenario baked (operator and modal), FBX / BVH / glTF export and re-import, the key-pose
picture and ergonomics plots, the snapshot render, the compiled kernels (Numba from the extension's wheels
inside Blender, its cache, the NumPy fallback), `batch.py` from a checkout and from the installed extension, bad
input and bad states, and disabling (nothing left registered).

Last run: {today} on {platform.platform()} (Python {platform.python_version()}),
{"all passed" if not failed else "FAILED on " + ", ".join(failed)}.

{table(legs)}

`.ci/run` runs the Blender {DEFAULT} leg (`tests/blender` with the default series) with the rest of the suite.
"""
    OUTPUT.write_text(text, encoding="utf-8")
    print(f"wrote {OUTPUT}: " + ("all passed" if not failed else f"failed on {', '.join(failed)}"))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
