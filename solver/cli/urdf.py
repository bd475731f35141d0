"""``python -m solver urdf PRESET | --file BODY.toml [-o OUT.urdf]``: a manikin as URDF (joints, limits, masses,
TCP frames), to a file or to standard output (:mod:`solver.io.urdf`)."""

from __future__ import annotations

import argparse

from ..errors import UsageError
from ..io.files import STDOUT, write_text
from .common import EXIT_OK, check_file_output


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The ``urdf`` subcommand on the command line's subparsers ``sub``."""
    p = sub.add_parser("urdf", help="export a manikin to URDF (joints, limits, masses, TCP frames)")
    p.add_argument("preset", nargs="?", help="manikin preset (see 'presets')")
    p.add_argument("--file", help="body TOML instead of a preset")
    p.add_argument("-o", "--output", help="URDF file to write (default: standard output)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Load the manikin and write its URDF (a file: one line saying so); exit code 0."""
    check_file_output(args.output, args.file)
    if (args.preset is None) == (args.file is None):
        raise UsageError("urdf needs a manikin preset name or --file BODY.toml (one of them)")
    from ..io.scenario.bodies import load_body
    from ..io.urdf import model_to_urdf, write_urdf

    model = load_body(preset=args.preset, file=args.file)
    if args.output and args.output != STDOUT:
        print(f"wrote {write_urdf(model, args.output)} ({model.n} joints, {len(model.tcps)} TCP frames)")
    else:
        write_text(STDOUT, model_to_urdf(model))
    return EXIT_OK
