"""The body mesh's math runs where the Blender layer runs it: in a Blender-equivalent environment (the bpy wheel and
numpy, no scipy), from the checkout, without loading scipy."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

from environments import ROOT

SCRIPT = """
import json, sys
import solver
from solver.bodymesh import fit_body
body = fit_body(solver.load_preset("female_5"))
print(json.dumps({"scipy": "scipy" in sys.modules, "vertices": len(body.vertices), "bones": len(body.bone_names),
                  "worst": max(body.fit_error.values())}))
"""


def test_fit_body_needs_only_numpy(blender_python: Path) -> None:
    done = subprocess.run([str(blender_python), "-c", SCRIPT], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    seen = json.loads(done.stdout.strip().splitlines()[-1])
    assert seen == {"scipy": False, "vertices": 13380, "bones": 73, "worst": seen["worst"]} and seen["worst"] < 0.07
