"""``python -m solver validate [--out DIR] [--split held-out|train|all] [--key-frame NAME ...] [--model M]
[--no-picture]``: the predictions held against motion-capture key frames (:mod:`solver.validation`): per key
frame, per task kind, per split and in total, the error of each posture measure, written as JSON, CSV, Markdown
and a PNG. ``--model standard`` solves with the standard comfort from the zero pose (a solve's default)."""

from __future__ import annotations

import argparse
from pathlib import Path

from .common import EXIT_NOT_CONVERGED, EXIT_OK, check_folder_name


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The ``validate`` subcommand on the command line's subparsers ``sub``."""
    p = sub.add_parser("validate", help="hold the predictions against motion capture: errors per posture measure")
    p.add_argument("--out", default="validation", help="folder for the JSON, CSV, Markdown, PNG (default ./validation)")
    p.add_argument("--split", default="all", choices=["all", "train", "held-out"], help="the subjects (default all)")
    p.add_argument("--manifest", help="a manifest TOML of key frames (default presets/validation/manifest.toml)")
    p.add_argument("--key-frame", action="append", default=[], help="only this key frame (repeatable)")
    p.add_argument("--model", default="behaviour", choices=["behaviour", "standard"],
                   help="the behaviour model (default) or the standard comfort from the zero pose (a solve's default)")
    p.add_argument("--no-picture", action="store_true", help="do not draw the PNG")
    p.add_argument("-q", "--quiet", action="store_true", help="do not print the summary")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run the key frames, write the outputs; 0 if every key frame converged, else 3."""
    from ..validation.harness import MANIFEST, run_validation
    from ..validation.report import summary_table, write_outputs

    check_folder_name(args.out)
    behaviour = args.model == "behaviour"
    report = run_validation(args.manifest or MANIFEST, args.split, tuple(args.key_frame), behaviour=behaviour)
    paths = write_outputs(report, Path(args.out), picture=not args.no_picture)
    s = report["summary"]
    if not args.quiet:
        print(f"{s['count']} key frames ({args.split}, {args.model} model), {s['converged']} converged")
        print("\n".join(summary_table(s["total"])))
        for split, stats in s["split"].items():
            means = ", ".join(f"{k} {v['mean_abs']:.3g}" for k, v in stats.items())
            print(f"{split}: mean abs error {means}")
        print("wrote " + ", ".join(str(p) for p in paths))
    return EXIT_OK if s["converged"] == s["count"] else EXIT_NOT_CONVERGED
