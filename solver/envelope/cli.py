"""``python -m solver envelope [MANIKIN ...] [--family DIR] -o DIR [--hand right|left|both] [--frequency F]
[--hemisphere H] [--load KG] [--rotation W,X,Y,Z] [--tolerance M] [--sole-scale S] [--processes N] [--no-plot]
[-q]``: balanced reach envelopes, one per manikin (a preset name or body TOML; every member of a family) and hand,
written into a new or empty folder (:mod:`.outputs`), several at once in worker processes. Bad arguments exit 2
with one line before any work."""

from __future__ import annotations

import argparse
import os
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

from ..errors import UsageError

if TYPE_CHECKING:
    import numpy as np

    from .directions import DirectionSphere
    from .sweep import Envelope

HANDS = {"right": ("right",), "left": ("left",), "both": ("right", "left")}


def add_envelope_parser(sub: argparse._SubParsersAction) -> None:
    """The ``envelope`` subcommand on the command line's subparsers ``sub``."""
    from .directions import HEMISPHERES

    p = sub.add_parser("envelope", help="reach envelopes in balance and without it: CSV, OBJ, GLB and PNG")
    p.add_argument("manikins", nargs="*", help="manikin presets or body TOMLs (default male_50 without --family)")
    p.add_argument("--family", help="a family folder (family.toml): one envelope per member")
    p.add_argument("-o", "--output", required=True, help="folder to write (new or empty)")
    p.add_argument("--hand", default="right", choices=sorted(HANDS), help="which hand (default right)")
    p.add_argument("--frequency", type=int, default=3,
                   help="geodesic sphere frequency F: 10 F^2 + 2 directions (default 3: 92)")  # fmt: skip
    p.add_argument("--hemisphere", default="all", choices=list(HEMISPHERES),
                   help="only the directions of this half (default all)")  # fmt: skip
    p.add_argument("--load", type=float, default=0.0, help="kg held in the hand (default 0)")
    p.add_argument("--rotation", help="fix the hand's orientation to this quaternion w,x,y,z (default free)")
    p.add_argument("--tolerance", type=float, default=0.02, help="reach resolution, m (default 0.02)")
    p.add_argument("--sole-scale", type=float, default=1.0,
                   help="keep the centre of pressure in the soles scaled by this (default 1: whole soles)")  # fmt: skip
    p.add_argument("--processes", type=int, help="envelopes computed at once (default: all cores)")
    p.add_argument("--no-plot", action="store_true", help="do not write the PNG sections")
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary and no progress")
    p.set_defaults(run=run_envelope)


def _manikins(args: argparse.Namespace) -> list[str]:
    """The manikins to run: the named ones, then the family's members (body file paths)."""
    names = list(args.manikins)
    if args.family is not None:
        from ..population import read_family

        names += [str(path) for path in read_family(args.family).files]
    return names or ["male_50"]


def _rotation(text: str | None):
    """The fixed hand orientation (3x3) of ``--rotation w,x,y,z``, None for free."""
    if text is None:
        return None
    from ..spatial import quat_to_matrix
    from .run import rotation_of

    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise UsageError(f"--rotation: expected 4 numbers w,x,y,z, got {text!r}") from None
    return quat_to_matrix(rotation_of(values))


class Settings(NamedTuple):
    """What every envelope of a run shares (see :func:`solver.envelope.sweep.sweep_envelope`)."""

    load_kg: float
    rotation: np.ndarray | None
    tolerance: float
    sole_scale: float


def _one(name: str, side: str, sphere: DirectionSphere, settings: Settings, shown=None) -> Envelope:
    """One envelope (in a worker process: the model is loaded there from its name)."""
    from ..bodies import load_preset
    from .sweep import sweep_envelope

    s = settings
    return sweep_envelope(load_preset(name), sphere, side, s.load_kg, s.rotation, s.tolerance, shown, s.sole_scale)


def _sweeps(runs: list, sphere: DirectionSphere, settings: Settings, processes: int, progress) -> Iterator[Envelope]:
    """The envelope of each (manikin, hand) of ``runs``: in this process with a progress line per direction, or in
    ``processes`` worker processes (as they finish, progress per envelope)."""
    n = len(sphere.directions)
    if processes <= 1 or len(runs) <= 1:
        for k, (name, side) in enumerate(runs):
            yield _one(name, side, sphere, settings, lambda done, _total, before=k * n: progress.update(before + done))
        return
    from concurrent.futures import ProcessPoolExecutor, as_completed

    with ProcessPoolExecutor(min(processes, len(runs))) as pool:
        futures = [pool.submit(_one, name, side, sphere, settings) for name, side in runs]
        for k, future in enumerate(as_completed(futures), 1):
            progress.update(k * n)
            yield future.result()


def _check(args: argparse.Namespace) -> tuple[list, DirectionSphere, Settings]:
    """Every argument checked before any work: ((manikin, hand) runs, the directions, the settings)."""
    from ..bodies import load_preset
    from ..population.family_files import check_family_folder
    from .directions import direction_sphere
    from .reach import check_tolerance, reach_setup

    if not str(args.output).strip():
        raise UsageError("-o: expected a folder name, got ''")
    if args.processes is not None and args.processes < 1:
        raise UsageError(f"--processes: expected a whole number >= 1, got {args.processes}")
    sphere = direction_sphere(args.frequency, args.hemisphere)
    settings = Settings(args.load, _rotation(args.rotation), check_tolerance(args.tolerance), args.sole_scale)
    names = _manikins(args)
    models = [load_preset(name) for name in names]
    for model in models:
        for side in HANDS[args.hand]:  # refuses a load, a sole scale or a body that cannot be done
            reach_setup(model, side, settings.load_kg, settings.rotation, True, settings.sole_scale)
    if len({m.name for m in models}) < len(models):
        raise UsageError("manikins: two have the same name; their files would overwrite each other")
    check_family_folder(args.output)
    return [(name, side) for name in names for side in HANDS[args.hand]], sphere, settings


def run_envelope(args: argparse.Namespace) -> int:
    """Check everything, then sweep each manikin and hand and write its files as it is done; exit code 0."""
    from ..progress import Progress
    from .analysis import comparison, summary_lines
    from .outputs import summary_row, write_envelope, write_summary

    runs, sphere, settings = _check(args)
    folder = Path(args.output)
    folder.mkdir(parents=True, exist_ok=True)
    progress = Progress(len(runs) * len(sphere.directions), enabled=not args.quiet, what="directions")
    processes = args.processes if args.processes is not None else (os.cpu_count() or 1)
    rows = []
    for envelope in _sweeps(runs, sphere, settings, processes, progress):
        stats = comparison(envelope)
        write_envelope(envelope, stats, folder, plot=not args.no_plot)
        rows.append(summary_row(envelope, stats))
        write_summary(rows, folder)
        if not args.quiet:
            progress.clear()
            print("\n".join(summary_lines(envelope, stats)))
    if not args.quiet:
        print(f"wrote {len(runs)} envelopes into {folder} (see {folder / 'envelopes.csv'})")
    return 0
