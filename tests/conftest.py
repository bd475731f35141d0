"""Shared fixtures (the helpers they use are in helpers.py, importable from every test module)."""

from __future__ import annotations

import os
import signal

import pytest
from helpers import random_tree
from hypothesis import settings

from solver import kernels
from solver.body.model import Model

# Property tests draw the same examples on every run, so a verdict never depends on the run's luck (CI gets one
# run); HYPOTHESIS_PROFILE=explore draws new ones, for looking for trouble by hand.
settings.register_profile("repeatable", derandomize=True)
settings.register_profile("explore", derandomize=False)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "repeatable"))


def pytest_configure(config: pytest.Config) -> None:
    """Ctrl-C (SIGINT) as Python takes it by default, also when the runner was started ignoring it: a shell without
    job control (a script, ``pytest ... &``) starts background commands with SIGINT ignored, and every process they
    start inherits that through exec. The Ctrl-C tests (a CLI solve, a Blender bake, a study cancelled from Blender)
    send SIGINT to processes started from this one, which would never see it (a cancelled study then ran on to its
    end before it stopped)."""
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)


def _children_on_numpy_kernels() -> None:
    """This process uses the kernels MANIKIN_KERNELS asks for (Numba where it imports: the kernel tests compare
    both paths here); the processes tests start (a CLI command, a study's workers, Blender sessions) solve on the
    NumPy kernels unless a test asks for others: each would spend ~0.6 s importing Numba and loading the compiled
    kernels, and the kernels' own subprocess tests set MANIKIN_KERNELS themselves."""
    kernels.active()  # decided now, from the environment as it was
    os.environ.setdefault("MANIKIN_KERNELS", "numpy")


_children_on_numpy_kernels()


@pytest.fixture(params=[0, 1, 2])
def tree(request) -> Model:
    return random_tree(request.param)
