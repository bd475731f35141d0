"""What a problem builds from its model and a few plain inputs, built once per model and handed out again.

A study's worker builds a problem per run for the same body (and a motion's restarts rebuild it): the comfort
terms, the contact set and its statics layout, the floor's and the body's own clearance rows are the same every
time. Models are frozen, so a model (by identity) and a key of every other input the built object
depends on (exact: bytes of arrays, ``repr`` of floats) name it. An object that keeps state while it is solved
(a clearance's last query) is kept as a template, never solved, and a shallow copy of it is handed out
(:func:`fresh`): what a new build gives. What is kept refers to its model, so a few models are kept, not a weak
mapping (its values would keep their keys alive).
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Hashable
from typing import TypeVar

import numpy as np

from ..body.model import Model

T = TypeVar("T")
MODELS = 8  # models kept, oldest dropped first (as a study's worker keeps its bodies: solver.study.runner)
ENTRIES = 16  # kept per model, oldest dropped first (a study varying a load makes a new key a run; a layout ~0.5 MB)
_PER_MODEL: dict[Model, dict] = {}  # by identity (models are frozen, compared by identity)
_LOCK = threading.Lock()  # a Dask worker may run tasks in threads


def per_model(model: Model, key: Hashable, build: Callable[[], T]) -> T:
    """``build()``, once per ``model`` and ``key`` (every input of ``build`` but the model); not to be written to."""
    known = _PER_MODEL.get(model)
    if known is not None:
        found = known.get(key, _MISSING)
        if found is not _MISSING:
            return found
    value = build()
    with _LOCK:
        known = _PER_MODEL.get(model)
        if known is None:
            if len(_PER_MODEL) >= MODELS:
                _PER_MODEL.pop(next(iter(_PER_MODEL)))
            known = _PER_MODEL[model] = {}
        if len(known) >= ENTRIES:
            known.pop(next(iter(known)))
        known[key] = value
    return value


def fresh(template: T) -> T:
    """A shallow copy of ``template`` (its constants shared, its own state as new), without its reduce protocol."""
    twin = object.__new__(type(template))
    twin.__dict__.update(template.__dict__)
    return twin


def exact(array: np.ndarray | None) -> tuple | None:
    """A key of ``array``'s exact values (shape and bytes as float64; None stays None)."""
    if array is None:
        return None
    values = np.asarray(array, dtype=float)
    return values.shape, values.tobytes()


_MISSING = object()
