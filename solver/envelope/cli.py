"""``python -m solver envelope [MANIKIN ...] [--family DIR] -o DIR [--hand right|left|both] [--frequency F]
[--hemisphere H] [--load KG] [--rotation W,X,Y,Z] [--tolerance M] [--no-plot] [-q]``: balanced reach envelopes,
one per manikin (a preset name or body TOML; every member of a family) and hand, written into a new or empty folder
(:mod:`.outputs`). Bad arguments exit 2 with one line before any work."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import UsageError

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


def run_envelope(args: argparse.Namespace) -> int:
    """Check everything, then sweep each manikin and hand and write its files as it is done; exit code 0."""
    from ..bodies import load_preset
    from ..population.family_files import check_family_folder
    from ..progress import Progress
    from .analysis import comparison, summary_lines
    from .directions import direction_sphere
    from .outputs import summary_row, write_envelope, write_summary
    from .reach import check_tolerance, reach_setup
    from .sweep import sweep_envelope

    if not str(args.output).strip():
        raise UsageError("-o: expected a folder name, got ''")
    sphere = direction_sphere(args.frequency, args.hemisphere)
    rotation = _rotation(args.rotation)
    check_tolerance(args.tolerance)
    models = [load_preset(name) for name in _manikins(args)]
    for model in models:
        for side in HANDS[args.hand]:
            reach_setup(model, side, args.load, rotation)  # refuses a load or a body that cannot be done
    if len({m.name for m in models}) < len(models):
        raise UsageError("manikins: two have the same name; their files would overwrite each other")
    check_family_folder(args.output)
    folder = Path(args.output)
    folder.mkdir(parents=True, exist_ok=True)
    runs = [(model, side) for model in models for side in HANDS[args.hand]]
    progress = Progress(len(runs) * len(sphere.directions), enabled=not args.quiet, what="directions")
    rows = []
    for k, (model, side) in enumerate(runs):

        def shown(done: int, _total: int, before: int = k * len(sphere.directions)) -> None:
            progress.update(before + done)

        envelope = sweep_envelope(model, sphere, side, args.load, rotation, args.tolerance, shown)
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
