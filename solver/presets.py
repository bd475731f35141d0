"""Where the shipped presets are: ``presets/`` at the repository (extension) root. Paths only, light to import."""

from __future__ import annotations

from pathlib import Path

PRESETS_DIR = Path(__file__).resolve().parents[1] / "presets"
MANIKINS_DIR = PRESETS_DIR / "manikins"


def list_presets() -> list[str]:
    """Names of the shipped manikin presets (file stems in ``presets/manikins``), sorted."""
    return sorted(p.stem for p in MANIKINS_DIR.glob("*.toml")) if MANIKINS_DIR.is_dir() else []
