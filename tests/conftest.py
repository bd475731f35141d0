"""Shared fixtures (the helpers they use are in helpers.py, importable from every test module)."""

from __future__ import annotations

import signal

import pytest
from helpers import random_tree

from solver.body.model import Model


def pytest_configure(config: pytest.Config) -> None:
    """Ctrl-C (SIGINT) as Python takes it by default, also when the runner was started ignoring it: a shell without
    job control (a script, ``pytest ... &``) starts background commands with SIGINT ignored, and every process they
    start inherits that through exec. The Ctrl-C tests (a CLI solve, a Blender bake, a study cancelled from Blender)
    send SIGINT to processes started from this one, which would never see it (a cancelled study then ran on to its
    end before it stopped)."""
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)


@pytest.fixture(params=[0, 1, 2])
def tree(request) -> Model:
    return random_tree(request.param)
