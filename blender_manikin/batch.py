"""Bake a manikin motion headlessly and write the .blend, exports, a report and a picture.

    blender --background [scene.blend] --python blender_manikin/batch.py -- ARGS
    python blender_manikin/batch.py ARGS                       (with the bpy module: pip install bpy)

ARGS: --scenario S.toml (a new manikin with keyed target empties) and/or --blend FILE.blend (or the .blend Blender
opened), or --operations OPS.toml (a new manikin, the file's objects and operations imported as Import Operations does,
the motion generated in this process as ``manikin operate`` generates it and keyed as Generate Motion keys it: the
armature and the objects; no --scenario, --blend, --manikin, --frames or --retarget), --manikin NAME (when the scene has
several), --frames START END (default: the scenario's motion or the scene's range), --out OUT.blend, --export
OUT.fbx|OUT.bvh|OUT.glb|OUT.gltf (repeatable), --report REPORT.json, --result RESULT.json (the format of python -m
solver solve), --picture KEY_POSES.png, --plots PREFIX (ergonomics plots PREFIX_loads.png, PREFIX_scores.png,
PREFIX_back.png), --retarget RIG|ARMATURE (key the baked motion onto a shipped rig built beside the manikin:
mpfb_default, game_engine, mixamo, cmu_mb, rigify; or onto an armature of the .blend; the exports then write it instead
of the manikin), -q.

Exit codes: 0 every frame converged, 3 some frame did not (all outputs are still written), 2 bad input or a file
that cannot be written (one line on stderr; each file is written beside its name, checked and renamed, so a full
disk leaves the old file), 130 Ctrl-C (the frames solved so far are keyed and kept in the result, the report and
the .blend). Bad input that needs no scene (the arguments, the output paths, the input files) is found before bpy
is imported: it costs no Blender start. Run as a script, this file loads the extension it belongs to from its own
location (a checkout or an installed extension) under the package name ``manikin`` and registers it, unless Blender
already has that copy enabled.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import os
import shutil
import sys
from collections.abc import Callable
from pathlib import Path
from types import ModuleType
from typing import Any

ROOT = Path(__file__).resolve().parents[1]  # the extension root: blender_manifest.toml, __init__.py, solver/, ...
PACKAGE = "manikin"
EXIT_OK, EXIT_BAD_INPUT, EXIT_NOT_CONVERGED, EXIT_INTERRUPTED = 0, 2, 3, 130


def _errors() -> ModuleType:
    """``solver.errors``: of the package this file belongs to, or (run as a script, outside any package) loaded
    from ``solver/errors.py`` beside it, which imports nothing heavy."""
    if __package__:
        root = __package__.rpartition(".")[0]
        return importlib.import_module(f"{root}.solver.errors" if root else "solver.errors")
    spec = importlib.util.spec_from_file_location("_manikin_batch_errors", ROOT / "solver" / "errors.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


ERRORS = _errors()


class BadInput(ERRORS.UsageError):
    """A user error: reported as one line, exit code 2 (a ``solver.errors.UsageError``, so a ``ManikinError``)."""


def parser() -> argparse.ArgumentParser:
    p = ERRORS.ArgumentParser(prog="batch.py", description=__doc__.splitlines()[0])  # a bad argument: one line
    p.add_argument("--scenario", type=Path, help="scenario TOML: creates the manikin and its (keyed) targets")
    p.add_argument("--blend", type=Path, help="open this .blend first (its manikin and animated targets)")
    p.add_argument("--operations", type=Path, help="operations scenario TOML ([[objects]], [[operations]]): a new "
                   "manikin, the motion generated from the operations")  # fmt: skip
    p.add_argument("--manikin", help="the armature to bake when the scene has several manikins")
    p.add_argument("--frames", type=int, nargs=2, metavar=("START", "END"), help="frame range (inclusive)")
    p.add_argument("--out", type=Path, help="save the baked scene as this .blend")
    p.add_argument("--export", type=Path, action="append", default=[], help="FBX, BVH or glTF file (repeatable)")
    p.add_argument("--report", type=Path, help="JSON report: per frame convergence, times, residuals, ergonomics")
    p.add_argument("--result", type=Path, help="result JSON as written by python -m solver solve")
    p.add_argument("--picture", type=Path, help="PNG of key poses (small Cycles renders side by side)")
    p.add_argument(
        "--plots",
        type=Path,
        metavar="PREFIX",
        help="ergonomics plots PREFIX_loads.png, "
        "PREFIX_scores.png, PREFIX_back.png (joint loads, RULA/REBA, back and arms per frame)",
    )
    p.add_argument(
        "--retarget",
        metavar="RIG",
        help="key the baked motion onto a shipped rig (mpfb_default, game_engine, mixamo, cmu_mb, rigify) built beside "
        "the manikin, or onto an armature of the .blend; --export then writes that armature",
    )
    p.add_argument("-q", "--quiet", action="store_true", help="print errors only")
    return p


def parse(argv: list[str]) -> argparse.Namespace:
    """Parsed arguments; a UsageError (BadInput) with one line for anything wrong."""
    args = parser().parse_args(argv)
    if args.out is not None and args.out.suffix.lower() != ".blend":
        raise BadInput(f"--out {args.out}: expected a .blend file")
    if args.picture is not None and args.picture.suffix.lower() != ".png":
        raise BadInput(f"--picture {args.picture}: expected a .png file")
    if args.operations is not None:
        given = [f"--{name}" for name in ("scenario", "blend", "manikin", "frames", "retarget") if getattr(args, name)]
        if given:
            raise BadInput(f"--operations makes its own manikin and frames from the file: leave out {', '.join(given)}")
    return args


def script_args(argv: list[str]) -> list[str]:
    """This script's arguments: after ``--`` (Blender's convention), else everything after the script name."""
    if "--" in argv:
        return argv[argv.index("--") + 1 :]
    return [] if Path(argv[0]).stem.lower().startswith("blender") else argv[1:]


def extension_package() -> ModuleType:
    """The extension package at ROOT imported as ``manikin``, not registered: its ``__init__`` imports nothing, so
    this needs no bpy (its modules that use bpy import it when they are imported)."""
    init = ROOT / "__init__.py"
    module = sys.modules.get(PACKAGE)
    if module is None or Path(getattr(module, "__file__", "") or "").resolve() != init:
        spec = importlib.util.spec_from_file_location(PACKAGE, init, submodule_search_locations=[str(ROOT)])
        module = importlib.util.module_from_spec(spec)
        sys.modules[PACKAGE] = module
        spec.loader.exec_module(module)
    return module


def load_extension() -> tuple[ModuleType, bool]:
    """The extension package at ROOT, registered: an enabled add-on of that folder, else imported as ``manikin``;
    and whether this call registered it (then :func:`main` unregisters it before exit: bpy 4.5 hangs at exit
    otherwise).

    Another enabled copy of Manikin (a different folder) is disabled for this session, so its classes do not
    clash with ours; its wheels stay installed (no refresh), so this copy can use them.
    """
    import bpy

    addon_utils = importlib.import_module("addon_utils")  # on the path once bpy is imported

    init = ROOT / "__init__.py"
    for name in list(bpy.context.preferences.addons.keys()):
        module = sys.modules.get(name)
        if module is None or not hasattr(module, "blender_manikin"):
            continue
        if Path(getattr(module, "__file__", "") or "").resolve() == init:
            return module, False
        addon_utils.disable(name, refresh_handled=True)
    module = extension_package()
    if hasattr(bpy.types, "MANIKIN_OT_bake_motion"):
        return module, False
    module.register()
    return module, True


def missing_dependency(exc: ImportError) -> str:
    """One line saying what is missing and how a user gets it."""
    name = exc.name or str(exc)
    if name.split(".")[0] == "bpy":
        return "this script runs inside Blender: blender --background --python batch.py -- ARGS (or pip install bpy)"
    return (
        f"{name} is missing: install the Manikin extension zip for your platform in this Blender (its wheels "
        f"bring {name}), or run with a Python that has it (pip install -r requirements.txt in a checkout)"
    )


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or type(exc).__name__


def job_of(extension: ModuleType, args: argparse.Namespace) -> Any:
    """The extension's ``Job`` (``blender_manikin.motion.job_input``, no bpy) for the parsed arguments."""
    job_input = importlib.import_module(f"{extension.__name__}.blender_manikin.motion.job_input")
    return job_input.Job(
        scenario=args.scenario,
        blend=args.blend,
        manikin=args.manikin,
        frames=tuple(args.frames) if args.frames else None,
        out=args.out,
        exports=args.export,
        report=args.report,
        result=args.result,
        picture=args.picture,
        plots=args.plots,
        retarget=args.retarget,
        quiet=args.quiet,
        operations=args.operations,
    )


def guarded(extension: ModuleType, step: Callable[[], int | None]) -> int | None:
    """``step()``; a user error (the extension's ManikinError, an OSError) one line on stderr and EXIT_BAD_INPUT,
    Ctrl-C outside the bake (which keeps its frames and says so itself) EXIT_INTERRUPTED."""
    errors = importlib.import_module(f"{extension.__name__}.solver.errors")
    try:
        return step()
    except (errors.ManikinError, OSError) as exc:
        print(f"error: {_one_line(exc)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED


def run_job(extension: ModuleType, job: Any) -> int:
    """Bake (or generate, for ``--operations``) and write with the loaded extension; its exit code."""
    if job.operations is not None:  # generated from the operations, not baked from targets
        run = importlib.import_module(f"{extension.__name__}.blender_manikin.operations.headless").run
    else:
        run = importlib.import_module(f"{extension.__name__}.blender_manikin.motion.job").run
    return guarded(extension, lambda: run(job))


def main(argv: list[str] | None = None) -> int:
    """Run with this script's arguments (default: from sys.argv); the exit code. What needs no scene (the
    arguments, the output paths, the input files) is checked before bpy is imported: a bad input costs no Blender
    start."""
    try:
        args = parse(script_args(sys.argv) if argv is None else argv)
    except ERRORS.UsageError as exc:
        print(f"error: {_one_line(exc)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    extension, registered = None, False
    os.environ.setdefault("MANIKIN_WARMUP", "0")  # registering starts no background compile: this run compiles itself
    try:
        if sys.modules.get("bpy") is not None:  # inside Blender: check with the copy that runs the job
            extension, registered = load_extension()
        package = extension or extension_package()
        job = job_of(package, args)
        checks = importlib.import_module(f"{package.__name__}.blender_manikin.motion.job_input")
        failed = guarded(package, lambda: checks.check_inputs(job))
        if failed is not None:
            return failed
        if extension is None:
            extension, registered = load_extension()
        return run_job(extension, job)
    except ImportError as exc:
        print(f"error: {missing_dependency(exc)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    finally:
        if registered:
            extension.unregister()  # bpy 4.5 hangs at exit with the add-on still registered


def exit_process(code: int) -> None:
    """Exit with ``code``. Inside the Blender binary that is sys.exit; as the bpy module, the process ends at once
    after flushing (and removing Blender's temp folder): bpy 4.2's module segfaults at exit after any glTF export
    (a static destructor calls into the finalized interpreter), which would turn every exit code into 139."""
    bpy = sys.modules.get("bpy")
    if bpy is None or bpy.app.binary_path:
        sys.exit(code)
    sys.stdout.flush()
    sys.stderr.flush()
    if Path(bpy.app.tempdir).name.startswith("blender_"):  # this session's own folder, never the configured one
        shutil.rmtree(bpy.app.tempdir, ignore_errors=True)
    os._exit(code)


if __name__ == "__main__":
    if sys.path and Path(sys.path[0]).resolve() == Path(__file__).resolve().parent:
        sys.path.pop(0)  # run as a script: our own folder on the path would shadow nothing useful, only confuse
    exit_process(main())
