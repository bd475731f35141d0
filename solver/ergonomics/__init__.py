"""Ergonomic evaluation of solved poses and motions (issue 6): joint loads, RULA, REBA, OWAS, NIOSH, a worksheet.

Works from a result file alone (README "result JSON"); the manikin named by the result's scenario (or
``ErgoOptions.manikin``) supplies joint strengths and the standard working area. One module, one job:
``frames`` (reading), ``manikin`` (strengths, working area), ``loads``, ``postures``, ``rula``, ``reba``, ``owas``,
``niosh``, ``worksheet``, ``report`` (JSON, CSV), ``plots`` (PNG).
"""

from __future__ import annotations

from pathlib import Path

from .frames import ErgonomicsInputError, read_result
from .options import ErgoOptions
from .report import evaluate, write_csv, write_json

__all__ = ["ErgoOptions", "ErgonomicsInputError", "evaluate", "read_result", "run"]


def run(result: str | Path, output: str | Path, options: ErgoOptions | None = None, plots: bool = True) -> dict:
    """Evaluate ``result`` and write ``output`` (JSON), the CSV beside it (same stem) and, if ``plots``, the PNGs
    ``<stem>_loads.png``, ``<stem>_scores.png`` and ``<stem>_back.png``. Returns the report and the written paths
    under ``"written"``."""
    options = options or ErgoOptions()
    try:
        options.check()
    except ValueError as exc:
        raise ErgonomicsInputError(f"options: {exc}") from None
    result, output = Path(result), Path(output)
    report = evaluate(read_result(result), options, result)
    write_json(report, output)
    written = [output, output.with_suffix(".csv")]
    write_csv(report, written[1])
    if plots:
        from .plots import write_plots

        written += write_plots(report, output.with_suffix(""))
    report["written"] = [str(p) for p in written]
    return report
