"""A command's start-up without the cyclic garbage collector (``StartupWithoutGC``): the collector is off only in the
start-up, back on (as it was) after, the start-up's objects frozen; garbage from compiling kernels is freed, not
frozen; and the solve command leaves the collector on."""

from __future__ import annotations

import gc
import weakref
from collections.abc import Iterator
from pathlib import Path

import pytest

from solver import kernels
from solver.cli.common import StartupWithoutGC
from solver.cli.main import main

SCENARIO = Path(__file__).resolve().parents[3] / "presets" / "scenarios" / "box_lift.toml"


class _Node:
    """An object in a reference cycle, which only the cyclic collector frees."""

    def __init__(self) -> None:
        self.me = self


@pytest.fixture(autouse=True)
def _collector_restored() -> Iterator[None]:
    was = gc.isenabled()
    yield
    gc.unfreeze()  # the frozen objects back in the oldest generation: this process collects them as before
    if was:
        gc.enable()
    else:
        gc.disable()


def test_the_collector_is_off_in_the_start_up_only_and_its_objects_are_frozen() -> None:
    gc.enable()
    with StartupWithoutGC() as startup:
        assert not gc.isenabled()
        kept = _Node()
        frozen_before = gc.get_freeze_count()
        startup.over()
        assert gc.isenabled() and gc.get_freeze_count() > frozen_before
        startup.over()  # a second call changes nothing
    assert gc.isenabled() and gc.is_tracked(kept)


def test_a_collector_turned_off_before_stays_off() -> None:
    gc.disable()
    with StartupWithoutGC():
        pass
    assert not gc.isenabled()


def test_leaving_the_block_ends_the_start_up_also_on_an_error() -> None:
    gc.enable()
    with pytest.raises(KeyError), StartupWithoutGC():
        raise KeyError("x")
    assert gc.isenabled()


def test_garbage_of_a_start_up_that_compiled_kernels_is_freed_not_frozen(monkeypatch: pytest.MonkeyPatch) -> None:
    gc.enable()
    with StartupWithoutGC():
        garbage = weakref.ref(_Node())
        assert garbage() is not None  # the collector is off: the cycle lives on
        monkeypatch.setitem(kernels._state, "compile_s", kernels.compile_seconds() + 1.0)  # as a compile would
    assert garbage() is None


def test_garbage_of_a_start_up_without_compiling_is_frozen() -> None:
    gc.enable()
    with StartupWithoutGC():
        garbage = weakref.ref(_Node())
    gc.collect()
    assert garbage() is not None  # out of the collections for good: cheap, as a start-up leaves little garbage


def test_the_solve_command_leaves_the_collector_on(tmp_path: Path) -> None:
    gc.enable()
    assert main(["solve", "-q", str(SCENARIO), "-o", str(tmp_path / "r.json")]) == 0
    assert gc.isenabled()


def _sum_of_squares(a):
    """A tiny loop for a kernel compiled in the test."""
    total = 0.0
    for v in a:
        total += v * v
    return total


def test_a_kernel_compiled_while_the_collector_is_off_frees_its_garbage(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """Compiling leaves much garbage (~0.2 GB over a cold cache): with the collector held off it is freed after each
    compile, and a kernel loaded or called again collects nothing."""
    if not kernels.active():
        pytest.skip(kernels.status())
    import numpy as np

    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))  # a cold cache of its own
    collected: list[int] = []
    monkeypatch.setattr(kernels.gc, "collect", lambda *args: collected.append(1) or 0)
    gc.disable()
    compiled = kernels.kernel(_sum_of_squares)
    assert compiled(np.array([1.0, 2.0])) == 5.0
    assert collected == [1]
    assert compiled(np.array([3.0])) == 9.0
    assert kernels.kernel(_sum_of_squares)(np.array([2.0])) == 4.0  # loaded from the cache: no compile
    assert collected == [1]
