"""Benchmarks that write docs/BENCHMARKS.md: preset scenarios (``scenarios``) and random targets
(``random_targets``, thesis §6.1.2)."""

from .scenarios import run_benchmarks, write_section

__all__ = ["run_benchmarks", "write_section"]
