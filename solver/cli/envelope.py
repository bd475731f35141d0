"""``python -m solver envelope [MANIKIN ...] [--family DIR] -o DIR [--hand right|left|both] [--frequency F]
[--hemisphere H] [--load KG] [--rotation W,X,Y,Z] [--tolerance M] [--sole-scale S] [--feet planted|step]
[--processes N] [--no-plot] [-q]``: balanced reach envelopes, one per manikin (a preset name or body TOML; every
member of a family) and hand, written into a new or empty folder (:mod:`solver.envelope.outputs`), several at once
in worker processes. Bad arguments exit 2 with one line before any work. The settings, the sweep and the files are
those of a study's ``[envelope]`` (:mod:`solver.envelope.job`)."""

from __future__ import annotations

import argparse
import os
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import UsageError
from .common import EXIT_OK, check_count, check_folder_name

if TYPE_CHECKING:
    from ..envelope.job import EnvelopeSettings
    from ..envelope.sweep import Envelope


# The names the options take, written out here so that the parser (``--help``) loads neither numpy nor scipy; they
# are the keys of envelope.job.HANDS, envelope.directions.HEMISPHERES and envelope.reach.FEET_MODES (a test says so).
HAND_NAMES = ("both", "left", "right")
HEMISPHERE_NAMES = ("all", "front", "back", "upper", "lower", "left", "right")
FEET_NAMES = ("planted", "step")


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The ``envelope`` subcommand on the command line's subparsers ``sub``."""
    p = sub.add_parser("envelope", help="reach envelopes in balance and without it: CSV, OBJ, GLB and PNG")
    p.add_argument("manikins", nargs="*", help="manikin presets or body TOMLs (default male_50 without --family)")
    p.add_argument("--family", help="a family folder (family.toml): one envelope per member")
    p.add_argument("-o", "--output", required=True, help="folder to write (new or empty)")
    p.add_argument("--hand", default="right", choices=HAND_NAMES, help="which hand (default right)")
    p.add_argument(
        "--frequency", type=int, default=3, help="geodesic sphere frequency F: 10 F^2 + 2 directions (default 3: 92)"
    )
    p.add_argument(
        "--hemisphere", default="all", choices=HEMISPHERE_NAMES, help="only the directions of this half (default all)"
    )
    p.add_argument("--load", type=float, default=0.0, help="kg held in the hand (default 0)")
    p.add_argument("--rotation", help="fix the hand's orientation to this quaternion w,x,y,z (default free)")
    p.add_argument("--tolerance", type=float, default=0.02, help="reach resolution, m (default 0.02)")
    p.add_argument(
        "--sole-scale",
        type=float,
        default=1.0,
        help="keep the centre of pressure in the soles scaled by this (default 1: whole soles)",
    )
    p.add_argument(
        "--feet",
        default="planted",
        choices=FEET_NAMES,
        help="planted (default), or step: each sole slides and turns on the floor",
    )
    p.add_argument("--processes", type=int, help="envelopes computed at once (default: all cores)")
    p.add_argument("--no-plot", action="store_true", help="do not write the PNG sections")
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary and no progress")
    p.set_defaults(run=run)


def _manikins(args: argparse.Namespace) -> list[str]:
    """The manikins to run: the named ones, then the family's members (body file paths)."""
    names = list(args.manikins)
    if args.family is not None:
        from ..population import read_family

        names += [str(path) for path in read_family(args.family).files]
    return names or ["male_50"]


def _rotation(text: str | None) -> tuple[float, ...] | None:
    """The fixed hand orientation (w, x, y, z) of ``--rotation w,x,y,z``, None for free."""
    if text is None:
        return None
    from ..envelope.run import rotation_of

    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise UsageError(f"--rotation: expected 4 numbers w,x,y,z, got {text!r}") from None
    return rotation_of(values)


def _one(name: str, side: str, settings: EnvelopeSettings, shown=None) -> tuple[Envelope, dict]:
    """One envelope and its statistics (in a worker process: the model is loaded there from its name)."""
    from ..envelope.job import compute_envelope
    from ..io.scenario.bodies import load_preset

    return compute_envelope(load_preset(name), side, settings, shown)


def _sweeps(runs: list, settings: EnvelopeSettings, directions: int, processes: int, progress) -> Iterator[tuple]:
    """(envelope, statistics) of each (manikin, hand) of ``runs``: in this process with a progress line per
    direction, or in ``processes`` worker processes (as they finish, progress per envelope)."""
    n = directions
    if processes <= 1 or len(runs) <= 1:
        for k, (name, side) in enumerate(runs):
            yield _one(name, side, settings, lambda done, _total, before=k * n: progress.update(before + done))
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    from ..threads import end_with_parent

    pool = ProcessPoolExecutor(min(processes, len(runs)), initializer=end_with_parent)
    try:
        futures = [pool.submit(_one, name, side, settings) for name, side in runs]
        for k, future in enumerate(as_completed(futures), 1):
            progress.update(k * n)
            yield future.result()
    except BaseException:  # Ctrl-C, SIGTERM, an error: the envelopes written are kept, the unfinished ones dropped
        pool.shutdown(wait=False, cancel_futures=True)
        for worker in multiprocessing.active_children():
            worker.terminate()
        raise
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def _check(args: argparse.Namespace) -> tuple[list, EnvelopeSettings]:
    """Every argument checked before any work: ((manikin, hand) runs, the settings)."""
    from ..envelope.job import HANDS, EnvelopeSettings, check_settings
    from ..io.scenario.bodies import load_preset
    from ..population.family_files import check_family_folder

    check_folder_name(args.output)
    check_count(args.processes, "--processes")
    settings = EnvelopeSettings(
        args.load, _rotation(args.rotation), args.tolerance, args.sole_scale, args.feet, args.frequency, args.hemisphere
    )
    settings.sphere()  # the directions are refused before the manikins are loaded
    names = _manikins(args)
    models = [load_preset(name) for name in names]
    for model in models:
        for side in HANDS[args.hand]:  # refuses a load, a sole scale or a body that cannot be done
            check_settings(model, side, settings)
    if len({m.name for m in models}) < len(models):
        raise UsageError("manikins: two have the same name; their files would overwrite each other")
    check_family_folder(args.output)
    return [(name, side) for name in names for side in HANDS[args.hand]], settings


def run(args: argparse.Namespace) -> int:
    """Check everything, then sweep each manikin and hand and write its files as it is done; exit code 0."""
    from ..envelope.analysis import summary_lines
    from ..envelope.outputs import summary_row, write_envelope, write_summary
    from ..progress import Progress

    runs, settings = _check(args)
    folder = Path(args.output)
    folder.mkdir(parents=True, exist_ok=True)
    directions = len(settings.sphere().directions)
    progress = Progress(len(runs) * directions, enabled=not args.quiet, what="directions")
    processes = args.processes if args.processes is not None else (os.cpu_count() or 1)
    rows = []
    for envelope, stats in _sweeps(runs, settings, directions, processes, progress):
        write_envelope(envelope, stats, folder, plot=not args.no_plot)
        rows.append(summary_row(envelope, stats))
        write_summary(rows, folder)
        if not args.quiet:
            progress.clear()
            print("\n".join(summary_lines(envelope, stats)))
    if not args.quiet:
        print(f"wrote {len(runs)} envelopes into {folder} (see {folder / 'envelopes.csv'})")
    return EXIT_OK
