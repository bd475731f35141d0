"""``python -m solver family --sex male|female|both --coverage 0.95 --points 8 [--samples N --seed S] -o DIR``:
write a manikin family's body files and its index ``family.toml`` into a new or empty folder (exit 2 with one
line on bad arguments)."""

from __future__ import annotations

import argparse

from .common import EXIT_OK, check_folder_name

SEX_CHOICES = {"male": ("male",), "female": ("female",), "both": ("male", "female")}


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The ``family`` subcommand on the command line's subparsers ``sub``."""
    p = sub.add_parser("family", help="write a manikin family (boundary, mean and sampled bodies) as body TOMLs")
    p.add_argument("--sex", default="both", choices=sorted(SEX_CHOICES), help="which sexes (default both)")
    p.add_argument(
        "--coverage",
        type=float,
        default=0.95,
        help="share of the population inside the (stature, mass) ellipse (default 0.95)",
    )
    p.add_argument(
        "--points", type=int, default=8, help="boundary manikins per sex, 0 for none (default 8: axes and diagonals)"
    )
    p.add_argument("--samples", type=int, default=0, help="random manikins per sex (default 0)")
    p.add_argument("--seed", type=int, default=0, help="seed of the random manikins (default 0)")
    p.add_argument("-o", "--output", required=True, help="folder to write (new or empty)")
    p.add_argument("-q", "--quiet", action="store_true", help="print no summary")
    p.set_defaults(run=run)


def family_info(args: argparse.Namespace) -> dict:
    """The index's ``[family]`` table: the source and every argument, with the command that rewrites it."""
    from ..population.ansur2 import SOURCE

    command = (
        f"python -m solver family --sex {args.sex} --coverage {args.coverage:g} --points {args.points} "
        f"--samples {args.samples} --seed {args.seed}"
    )
    return {
        "source": SOURCE,
        "sexes": list(SEX_CHOICES[args.sex]),
        "coverage": args.coverage,
        "points": args.points,
        "samples": args.samples,
        "seed": args.seed,
        "command": command,
    }


def run(args: argparse.Namespace) -> int:
    """Make the family and write it; exit code 0."""
    from ..population.family import check_family_args, make_family
    from ..population.family_files import INDEX, check_family_folder, write_family

    check_folder_name(args.output)
    check_family_args(args.coverage, args.points, args.samples, args.seed)
    check_family_folder(args.output)
    members = make_family(SEX_CHOICES[args.sex], args.coverage, args.points, args.samples, args.seed)
    written = write_family(members, args.output, family_info(args))
    if not args.quiet:
        roles = ", ".join(
            f"{sum(m.role == r for m in members)} {r}"
            for r in ("boundary", "mean", "sample")
            if any(m.role == r for m in members)
        )
        print(f"wrote {len(members)} body files ({roles}) and {written[-1].parent / INDEX}")
    return EXIT_OK
