"""Ergonomic evaluation of solved poses and motions: joint loads, RULA, REBA, OWAS, NIOSH, a worksheet.

Works on typed frames (:class:`solver.io.result.frame.Frame`): from a :class:`~solver.Result` directly or from a
result file (docs/reference/result-file.md). The manikin (the result's own, ``ErgoOptions.manikin`` or the one the
result file's scenario names) supplies joint strengths and the standard working area. One module, one job:
``manikin`` (strengths, working area), ``loads``, ``postures``; the scores, one module each behind one
interface (``base``: :class:`~.base.Score`), listed in ``registry``: ``rula``, ``reba``, ``owas``, ``niosh``,
``worksheet``; ``report`` (the evaluation of all frames, JSON, CSV), ``stream`` (a result file frame by frame),
``plots`` (PNG). A new score is a module and a line in ``registry`` (docs/develop/recipes_score.md).
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from ..body.model import Model
from ..errors import UsageError
from ..io.result.frame import Frame, frame_of_result
from ..io.result.read import ResultFile
from ..iteration.result import Result
from .manikin import check_fits, resolve_model
from .options import ErgoOptions
from .registry import motion_scores
from .report import end_positions, evaluate_frames, output_files

__all__ = ["ErgoOptions", "evaluate", "output_files", "run"]

Source = Result | ResultFile | Iterable[Frame] | Iterable[tuple[int, Result]]


def evaluate(source: Source, options: ErgoOptions | None = None, model: Model | None = None) -> dict:
    """The ergonomic report of ``source``: a Result (frame 1), (frame, Result) pairs as :func:`solver.solve_motion`
    yields, a read result file (:func:`solver.read_result`) or typed frames.

    The manikin for strengths and the working area: ``model`` if given, else ``options.manikin`` (preset or
    body file), else the solved problem's own model, else the manikin of the result file's scenario.
    """
    options = checked(options)
    frames, own, scenario, path = _frames_of(source)
    check_frame_numbers(frames, options)
    if model is not None:
        note = f"model {model.name}"
    elif own is not None and not options.manikin:
        model, note = own, f"model {own.name} of the result"
    else:
        model, note = resolve_model(options.manikin, scenario, path.parent if path else Path("."))
        if options.manikin and frames:
            check_fits(model, frames[0], options.manikin)
    return evaluate_frames(frames, options, model, note, str(path) if path else None, scenario)


def checked(options: ErgoOptions | None) -> ErgoOptions:
    """``options`` (default: ErgoOptions()) after their check; a bad value is one UsageError line."""
    options = options or ErgoOptions()
    try:
        options.check()
    except ValueError as exc:
        raise UsageError(f"options: {exc}") from None
    return options


def check_frame_numbers(frames: list[Frame], options: ErgoOptions) -> None:
    """Refuse a frame number the options name (the NIOSH origin or destination) that is not a frame of the result
    (one UsageError line)."""
    numbers = [f.number for f in frames]
    for score in motion_scores():
        end_positions(score, numbers, options)


def _frames_of(source: Source) -> tuple[list[Frame], Model | None, str | None, Path | None]:
    """(frames, the solved problem's model or None, the scenario named, the result file's path)."""
    if isinstance(source, ResultFile):
        return source.frames, None, source.scenario, source.path
    items = [(1, source)] if isinstance(source, Result) else list(source)
    frames = [item if isinstance(item, Frame) else frame_of_result(item[1], item[0]) for item in items]
    own = next((item[1].problem.model for item in items if not isinstance(item, Frame)), None)
    return frames, own, None, None


def run(result: str | Path, output: str | Path, options: ErgoOptions | None = None, plots: bool = True) -> dict:
    """Evaluate the result file ``result`` (either format) frame by frame and write ``output`` (JSON), the CSV
    beside it (same stem) and, if ``plots``, the PNGs ``<stem>_loads.png``, ``<stem>_scores.png`` and
    ``<stem>_back.png``. Returns the report's entries but its frames, with ``frames`` = the frames a summary shows
    (all of up to 10 frames, else the first and the last), ``frame_count``, ``highest_reba`` (that frame's
    report), ``not_converged`` and ``not_held`` (frame numbers) and the written paths under ``"written"``
    (:func:`.stream.evaluate_file`)."""
    from .stream import evaluate_file

    return evaluate_file(result, Path(output), checked(options), plots)
