"""``python -m solver presets``: the manikin presets, and the scenario and family files that come with the
solver, as a user types them from here."""

from __future__ import annotations

import argparse
from pathlib import Path

from .common import EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The ``presets`` subcommand on the command line's subparsers ``sub``."""
    p = sub.add_parser("presets", help="list the manikin and scenario presets")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Print the three lists; exit code 0."""
    from ..io.scenario.bodies import PRESETS_DIR, list_presets

    print("manikins: " + ", ".join(list_presets()))
    scenarios = sorted((PRESETS_DIR / "scenarios").glob("*.toml"))
    print("scenarios: " + ", ".join(_from_here(p) for p in scenarios))
    families = sorted(p.parent for p in (PRESETS_DIR / "families").glob("*/family.toml"))
    print("families: " + ", ".join(_from_here(p) for p in families))
    return EXIT_OK


def _from_here(path: Path) -> str:
    """``path`` as a user types it here: relative to the working directory inside it (presets/... at the checkout's
    root), else absolute (the command runs from anywhere)."""
    try:
        return path.relative_to(Path.cwd().resolve()).as_posix()
    except ValueError:
        return str(path)
