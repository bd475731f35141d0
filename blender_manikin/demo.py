"""The demo: a 10 kg box taken off a low shelf and set onto a table, generated from its operations alone (no keyed
target) and rendered; and a hand put into a wall cabinet's compartment.

    python -m blender_manikin.demo [--out-dir out] [-q]

runs ``batch.py --operations`` on presets/operations/box_lift.toml (get the box, place it onto the table: the
generator plans the stance, the steps and the hands' ways, times them by MTM-1 and solves every frame in balance)
and writes ``box_lift.blend`` (the keyed manikin, the shelf and table as obstacles, the box keyed with the hands
and the operation list: open it in Blender 4.2+ with the extension), ``box_lift.glb`` and ``box_lift.bvh`` (the
motion for other tools), ``box_lift_report.json`` (per frame: convergence, times, residuals, RULA, REBA, OWAS,
joint loads, L4/L5 compression; the NIOSH lift from the grasp to the release) and ``box_lift_key_poses.png`` (key
poses side by side, with the shelf, table and box); then on presets/scenarios/cabinet_reach.toml (one pose, the
arm in between the cabinet's boards) ``cabinet_reach.blend`` and ``cabinet_reach.png``. Blender runs with a
throwaway user folder, so your own Blender settings and add-ons stay out of it. Exit codes as batch.py (the first
job's that failed).
"""

from __future__ import annotations

import argparse
import os
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OPERATIONS = ROOT / "presets" / "operations" / "box_lift.toml"  # no keyed target: generated from its operations
NAME = "box_lift"
REACH = ROOT / "presets" / "scenarios" / "cabinet_reach.toml"  # a single pose among obstacles
REACH_NAME = "cabinet_reach"


def batch_args(out_dir: Path, quiet: bool = False) -> list[str]:
    """The batch.py arguments of the demo's box lift (generated from its operations)."""
    out = out_dir / NAME
    args = ["--operations", str(OPERATIONS), "--out", f"{out}.blend", "--export", f"{out}.glb"]
    args += ["--export", f"{out}.bvh", "--report", f"{out}_report.json", "--picture", f"{out}_key_poses.png"]
    return args + (["-q"] if quiet else [])


def reach_args(out_dir: Path, quiet: bool = False) -> list[str]:
    """The batch.py arguments of the demo's cabinet reach (one pose: a .blend and its picture)."""
    out = out_dir / REACH_NAME
    return ["--scenario", str(REACH), "--out", f"{out}.blend", "--picture", f"{out}.png"] + (["-q"] if quiet else [])


def main(argv: list[str] | None = None) -> int:
    summary = " ".join(__doc__.split("\n\n")[0].split())  # the first paragraph, on one line
    parser = argparse.ArgumentParser(prog="python -m blender_manikin.demo", description=summary)
    parser.add_argument("--out-dir", type=Path, default=Path("out"), help="where the files go (default: out/)")
    parser.add_argument("-q", "--quiet", action="store_true", help="print errors only")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="manikin-demo-user-") as user:
        os.environ.setdefault("BLENDER_USER_RESOURCES", user)  # read before bpy is imported (in batch.main)
        from .batch import main as batch

        code = batch(batch_args(args.out_dir, args.quiet))
        if code != 2:
            code = code or batch(reach_args(args.out_dir, args.quiet))
    if code != 2 and not args.quiet:
        pictures = " and ".join(str(args.out_dir / name) for name in (NAME + "_key_poses.png", REACH_NAME + ".png"))
        print(f"look at {pictures}; open {args.out_dir / (NAME + '.blend')} in Blender")
    return code


if __name__ == "__main__":
    from .batch import exit_process  # as batch.py ends: bpy 4.2 would crash at a normal exit after a glTF export

    exit_process(main())
