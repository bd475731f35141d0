"""What installing, enabling and the first solve take as a user meets them, written to docs/BENCHMARKS.md.

    python -m bench.enable_timings [-o docs/BENCHMARKS.md] [--runs 5] [--series 4.2 4.5 5.0] [--before DIR]

For each Blender series it builds the linux-x64 zip with that series' bpy-only environment (.venvs/bpy-*: numpy,
no scipy), then per run, in fresh processes with a fresh user folder: installs and enables the zip (Preferences >
Install from Disk: Blender extracts the wheels), disables and enables it again, then in a second process (Blender
started again with the extension installed) enables it, adds a manikin and a hand target and times the first
Solve Pose (the solver and scipy load from the extension's wheels) and a second one. Wall-clock seconds.
``--before DIR`` (another checkout, e.g. ``git worktree add /tmp/before main``) measures that checkout's zip too,
the two zips taking turns run by run so that the shared machine's drift hits them alike: a before/after table.
"""

from __future__ import annotations

import argparse
import datetime
import io
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
import zipfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
VENVS = ROOT / ".venvs"
MODULE = "bl_ext.user_default.manikin"
MARK = "enable-timings"


def _child_install(zip_path: str) -> dict:
    import bpy

    t = time.perf_counter()
    bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default", enable_on_install=True)
    install = time.perf_counter() - t
    bpy.ops.preferences.addon_disable(module=MODULE)
    t = time.perf_counter()
    bpy.ops.preferences.addon_enable(module=MODULE)
    return {"install_and_enable": install, "enable_again": time.perf_counter() - t}


def _child_solve() -> dict:
    import bpy

    t = time.perf_counter()
    bpy.ops.preferences.addon_enable(module=MODULE)
    enable = time.perf_counter() - t
    bpy.ops.manikin.add_manikin(preset="male_50")
    bpy.ops.manikin.add_target(tcp="hand_r")
    bpy.context.active_object.location.x += 0.05
    t = time.perf_counter()
    assert bpy.ops.manikin.solve_pose() == {"FINISHED"}
    first = time.perf_counter() - t
    bpy.context.active_object.location.x -= 0.05
    t = time.perf_counter()
    bpy.ops.manikin.solve_pose()
    return {"enable_new_session": enable, "first_solve": first, "second_solve": time.perf_counter() - t}


def _run_child(python: Path, user: Path, *args: str) -> dict:
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(user))
    done = subprocess.run([str(python), __file__, "--child", *args], cwd=ROOT, env=env,  # bench/ needs scipy
                          capture_output=True, text=True, timeout=600)  # fmt: skip
    line = next((x for x in done.stdout.splitlines() if x.startswith(MARK)), None)
    if done.returncode != 0 or line is None:
        raise RuntimeError(done.stdout[-2000:] + done.stderr[-2000:])
    return json.loads(line[len(MARK) :])


def build_zip(python: Path, root: Path, out: str) -> Path:
    """The linux-x64 zip of the checkout ``root``, built by its own build module in ``out``."""
    built = subprocess.run([str(python), "-m", "blender_manikin.dev.build", "--output-dir", out, "--platform",
                            "linux-x64"], cwd=root, capture_output=True, text=True, check=True)  # fmt: skip
    return Path(built.stdout.strip())


def wheel_contents(zip_path: Path) -> dict[str, float]:
    """The wheels in a zip: how many, the files and folders Blender extracts from them, their size unpacked (MB)."""
    wheels = files = size = 0
    with zipfile.ZipFile(zip_path) as outer:
        for name in outer.namelist():
            if name.startswith("wheels/") and name.endswith(".whl"):
                with zipfile.ZipFile(io.BytesIO(outer.read(name))) as wheel:
                    infos = wheel.infolist()
                wheels, files, size = wheels + 1, files + len(infos), size + sum(i.file_size for i in infos)
    return {"wheels": wheels, "files": files, "unpacked_mb": size / 1e6, "zip_mb": zip_path.stat().st_size / 1e6}


def measure(series: str, runs: int, roots: dict[str, Path]) -> dict[str, dict]:
    """Per zip (label: checkout), its wheel contents and per step the seconds of each run on Blender ``series``."""
    python = next(VENVS.glob(f"bpy-{series}.*")) / "bin" / "python"
    with tempfile.TemporaryDirectory() as tmp:
        zips = {label: build_zip(python, root, str(Path(tmp, label))) for label, root in roots.items()}
        results = {label: dict(contents=wheel_contents(path), times={}) for label, path in zips.items()}
        for label, root in roots.items():
            head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=root, capture_output=True, text=True)
            results[label]["contents"]["commit"] = head.stdout.strip() or "?"
        for run in range(runs):
            for label, zip_path in zips.items():  # the zips take turns
                user = Path(tmp, f"user-{label}-{run}")
                seen = _run_child(python, user, "install", str(zip_path)) | _run_child(python, user, "solve")
                for step, seconds in seen.items():
                    results[label]["times"].setdefault(step, []).append(seconds)
                print(series, label, run, {k: round(v, 2) for k, v in seen.items()}, flush=True)
    return results


STEPS = {
    "install_and_enable": "Install from Disk, enabled on install (wheels extracted)",
    "enable_again": "disable, enable again (same session)",
    "enable_new_session": "enable in a new session (Blender started again)",
    "first_solve": "first Solve Pose (solver and scipy load)",
    "second_solve": "second Solve Pose",
}


def section(results: dict[str, dict[str, dict]], runs: int, command: str) -> str:
    """The Markdown section for docs/BENCHMARKS.md: per series and step, median and p95 of each zip."""
    cpu = Path("/proc/cpuinfo")
    names = [x.split(":", 1)[1].strip() for x in cpu.read_text().splitlines() if x.startswith("model name")] if (
        cpu.is_file()) else []  # fmt: skip
    system = f"{platform.system()} {platform.release()}"
    machine = f"{names[0] if names else platform.machine()}, {os.cpu_count()} cores, {system}"
    labels = list(next(iter(results.values())))
    lines = [f"<!-- {MARK}:start -->", "## Installing, enabling and the first solve", "",
             f"Written by `{command}` on {datetime.date.today()}; each run in fresh "
             "processes and a fresh user folder, the linux-x64 zip built by that series' own build tool, the bpy-only "
             "environments (Blender's Python: numpy, no scipy). Wall-clock seconds, median and 95th percentile of "
             f"the runs. Machine: {machine}, Python {platform.python_version()}.", ""]  # fmt: skip
    if len(labels) > 1:
        lines += [f"The zips took turns run by run: {' and '.join(labels)}.", ""]
    for label in labels:
        c = next(iter(results.values()))[label]["contents"]
        lines.append(
            f"- {label} (commit {c['commit']}): {c['wheels']} wheels, {c['files']:,} files and folders "
            f"({c['unpacked_mb']:.0f} MB unpacked) that Blender extracts on install and on every enable; the zip "
            f"{c['zip_mb']:.0f} MB."
        )
    lines += ["", "| Blender | step | " + " | ".join(f"{x} median s | {x} p95 s" for x in labels) + " |",
              "|---|---|" + "---:|---:|" * len(labels)]  # fmt: skip
    for series, by_zip in results.items():
        for step, label in STEPS.items():
            cells = []
            for zip_label in labels:
                values = np.array(by_zip[zip_label]["times"][step])
                cells += [f"{np.median(values):.2f}", f"{np.percentile(values, 95):.2f}"]
            lines.append(f"| {series} | {label} | " + " | ".join(cells) + " |")
    lines.append(f"<!-- {MARK}:end -->")
    return "\n".join(lines) + "\n"


def write(path: Path, text: str) -> None:
    """Replace the section between its marks in ``path``, or append it."""
    old = path.read_text(encoding="utf-8")
    start, end = f"<!-- {MARK}:start -->", f"<!-- {MARK}:end -->\n"
    if start in old:
        old = old[: old.index(start)] + text + old[old.index(end) + len(end) :]
    else:
        old = old.rstrip("\n") + "\n\n" + text
    path.write_text(old, encoding="utf-8")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.enable_timings", description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, default=ROOT / "docs" / "BENCHMARKS.md")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--series", nargs="+", default=["4.2", "4.5", "5.0"])
    parser.add_argument("--before", type=Path, help="another checkout whose zip is measured too, taking turns")
    parser.add_argument("--child", nargs="+", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        seen = _child_install(args.child[1]) if args.child[0] == "install" else _child_solve()
        print(MARK + json.dumps(seen), flush=True)
        os._exit(0)  # bpy 4.2 may segfault at exit (blender_manikin/batch.py exit_process)
    roots = {"before": args.before.resolve(), "now": ROOT} if args.before else {"now": ROOT}
    results = {series: measure(series, args.runs, roots) for series in args.series}
    command = f"python -m bench.enable_timings --runs {args.runs}" + (" --before DIR" if args.before else "")
    write(args.output, section(results, args.runs, command))
    return 0


if __name__ == "__main__":
    sys.exit(main())
