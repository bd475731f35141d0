"""The standard comfort terms, by name, each with its default weight: every problem's comfort unless it brings its
own terms, weighted by :class:`ComfortWeights` (a scenario's ``[comfort]`` keys, the keys of ``Result.comfort_parts``).

A new standard term is a new module with its :class:`~solver.comfort.base.ComfortTerm` and one ``register`` line
below (its name is the term's ``name``); the scenario reader and writer and the results then know it.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from typing import NamedTuple

from ..body.model import Model
from .base import ComfortTerm
from .contact_spread import ContactSpread
from .gaze import Gaze
from .joint_load import JointLoad
from .joint_range import JointRange
from .trunk_tilt import TrunkTilt


class StandardTerm(NamedTuple):
    """A registered standard term: ``factory`` makes it for a model; ``weight`` is its default (dimensionless)."""

    factory: Callable[[Model], ComfortTerm]
    weight: float


STANDARD_TERMS: dict[str, StandardTerm] = {}  # by name, in the order comfort sums them (and files list them)


def register(term: type[ComfortTerm], weight: float) -> None:
    """Make ``term`` (a ComfortTerm class, built from the model) a standard term of default ``weight``."""
    if term.name in STANDARD_TERMS:
        raise ValueError(f"standard comfort term {term.name!r} is registered already")
    STANDARD_TERMS[term.name] = StandardTerm(term, weight)


register(JointRange, 1.0)
register(JointLoad, 1.0)
register(ContactSpread, 0.01)
register(TrunkTilt, 5.0)  # the behaviour model, on by default (BEHAVIOUR_TRUNK); 0 is the standard model
register(Gaze, 0.0)  # the head toward the hands: off, the fit found no gain (mocap-validation.md); needs trunk > 0


class ComfortWeights(Mapping):
    """Weights of the standard comfort terms (dimensionless), one per registered term: by name,
    ``ComfortWeights(range=1.0, load=0.5)``, or in the registry's order, ``ComfortWeights(1.0, 0.5, 0.01)`` (range,
    load, contact, trunk, gaze); a term not given keeps its default. Read as attributes (``weights.load``) or as a
    mapping (``weights["load"]``, ``dict(weights)``). Frozen (:meth:`replace` makes another); equal when the
    weights are."""

    __slots__ = ("_values",)

    def __init__(self, *weights: float, **named: float) -> None:
        names = list(STANDARD_TERMS)
        if len(weights) > len(names):
            raise TypeError(f"ComfortWeights takes at most {len(names)} weights ({', '.join(names)}), got "
                            f"{len(weights)}")  # fmt: skip
        given = dict(zip(names, weights, strict=False))
        for name, weight in named.items():
            if name not in STANDARD_TERMS:
                raise TypeError(f"ComfortWeights: no standard comfort term {name!r} (known: {', '.join(names)})")
            if name in given:
                raise TypeError(f"ComfortWeights: the weight of {name!r} given twice")
            given[name] = weight
        values = {name: given.get(name, term.weight) for name, term in STANDARD_TERMS.items()}
        object.__setattr__(self, "_values", values)

    def __getattr__(self, name: str) -> float:
        if not name.startswith("_") and name in self._values:
            return self._values[name]
        raise AttributeError(f"ComfortWeights has no term {name!r}")

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError("ComfortWeights is frozen: make another (weights.replace(load=...))")

    def replace(self, **changes: float) -> ComfortWeights:
        """These weights with ``changes`` (by term name)."""
        return ComfortWeights(**{**self._values, **changes})

    def __getitem__(self, name: str) -> float:
        return self._values[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, ComfortWeights) and self._values == other._values

    def __hash__(self) -> int:
        return hash(tuple(self._values.items()))

    def __repr__(self) -> str:
        return "ComfortWeights(" + ", ".join(f"{k}={v!r}" for k, v in self._values.items()) + ")"

    def __reduce__(self) -> tuple:
        return _by_name, (dict(self._values),)


def _by_name(values: dict[str, float]) -> ComfortWeights:
    """ComfortWeights from a dict (what a pickled one is made again from)."""
    return ComfortWeights(**values)


DEFAULT_COMFORT = ComfortWeights()
# The behaviour model fitted against motion capture (docs/explanation/mocap-validation.md): a positive ``trunk``
# weight prices the trunk's lean and switches the range term to its posture tables (legs bend, elbows rest bent).
# On by default (the default weights are BEHAVIOUR); ``trunk = 0`` gives the standard model (STANDARD).
BEHAVIOUR_TRUNK = 5.0
BEHAVIOUR = DEFAULT_COMFORT.replace(trunk=BEHAVIOUR_TRUNK)
STANDARD = DEFAULT_COMFORT.replace(trunk=0.0, gaze=0.0)  # the standard comfort of the thesis: the behaviour model off


def behaviour_on(weights: Mapping[str, float]) -> bool:
    """Whether ``weights`` switch the behaviour model on (a positive ``trunk`` weight)."""
    return weights.get("trunk", 0.0) > 0.0


BEHAVIOUR_ONLY = ("gaze",)  # terms of the behaviour model beyond the trunk: weight 0 when it is off


def _weight(weights: Mapping[str, float], name: str, default: float, posture: bool) -> float:
    """The weight of term ``name`` in comfort: its own, or 0 for a behaviour term with the behaviour model off."""
    return weights.get(name, default) if posture or name not in BEHAVIOUR_ONLY else 0.0


def standard_terms(model: Model, weights: ComfortWeights = DEFAULT_COMFORT) -> list[tuple[float, ComfortTerm]]:
    """(weight, term) of every standard term for ``model``, in the registry's order (a term registered after
    ``weights`` were made has its default weight); the range term with its posture tables when
    :func:`behaviour_on`."""
    posture = behaviour_on(weights)
    return [(_weight(weights, name, term.weight, posture),
             JointRange(model, posture) if term.factory is JointRange and posture else term.factory(model))
            for name, term in STANDARD_TERMS.items()]  # fmt: skip
