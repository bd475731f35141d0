"""A result JSON frame's joints and links read in bulk (solver/io/result/read.py ``_usual_joints``,
``_usual_links``): the same arrays, bit for bit, as the checked one-by-one readers, and anything unusual (an int, a
null limit or strength side, a NaN, a missing value, an unknown link) goes through those readers, with their
defaults and messages."""

from __future__ import annotations

import copy
from itertools import islice
from pathlib import Path

import numpy as np
import pytest

import solver
from solver.errors import ResultFileError
from solver.io.result import read
from solver.io.table_reader import TableReader

BOX_LIFT_MOTION = Path(__file__).resolve().parents[4] / "presets" / "scenarios" / "box_lift_motion.toml"


@pytest.fixture(scope="module")
def raw_frames(tmp_path_factory) -> list[dict]:
    scenario = solver.load_motion(BOX_LIFT_MOTION)
    path = solver.write_result(tmp_path_factory.mktemp("bulk") / "r.json", islice(solver.solve_motion(scenario), 3))
    return [raw for _, raw in read.ResultStream(path).raw()]


def _one_by_one(raw: dict) -> tuple[tuple, dict]:
    t = TableReader("r.json", raw, "frames[0].", ResultFileError)
    links = read._links(t.table_list("links", non_empty=True))
    return links, read._joints(t.named_tables("joints"), {n: i for i, n in enumerate(links[0])})


def _equal(a, b) -> bool:
    if isinstance(a, np.ndarray):
        return isinstance(b, np.ndarray) and a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()
    if isinstance(a, (tuple, list)):
        return len(a) == len(b) and all(_equal(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, dict):
        return list(a) == list(b) and all(_equal(a[k], b[k]) for k in a)
    return a == b


def test_bulk_arrays_are_those_read_one_by_one(raw_frames: list[dict]) -> None:
    for raw in raw_frames:
        links, joints = _one_by_one(raw)
        quick_links = read._usual_links(raw["links"])
        lindex = {n: i for i, n in enumerate(links[0])}
        assert _equal(quick_links, links) and _equal(read._usual_joints(raw["joints"], lindex), joints)
        assert joints["joint_strength"] is not None and np.isinf(joints["joint_strength"]).any()


def _edit(raw: dict, edit) -> dict:
    out = copy.deepcopy(raw)
    edit(out)
    return out


def _first(raw: dict) -> dict:
    return next(iter(raw["joints"].values()))


@pytest.mark.parametrize(
    "edit",
    [
        lambda r: _first(r).update(value=0),  # an int
        lambda r: _first(r).update(min=None, max=-0.0),  # no lower limit; a signed zero
        lambda r: _first(r).update(strength=[None, 12.5]),  # unlimited one way
        lambda r: [jt.update(strength=None) for jt in r["joints"].values()],  # no strengths at all
        lambda r: _first(r).pop("value"),  # the default 0.0
        lambda r: _first(r).update(type="prismatic"),
        lambda r: r["links"][0].update(parent=None, mass=0),
        lambda r: _first(r).update(axis=[0.0, 0.0, 2.0]),  # normalised
    ],
)
def test_unusual_values_read_as_the_checked_readers_read_them(raw_frames: list[dict], edit) -> None:
    raw = _edit(raw_frames[0], edit)
    quick = read._frame(TableReader("r.json", raw, "frames[0].", ResultFileError))
    links, joints = _one_by_one(raw)
    checked = dict(joints, link_names=links[0], link_parent=links[1], link_mass=links[2], link_com=links[3])
    assert all(_equal(getattr(quick, k), v) for k, v in checked.items())


@pytest.mark.parametrize(
    "edit, message",
    [
        (lambda r: _first(r).update(value=float("nan")), "root_tx.value: expected a number in [-10000, 10000]"),
        (lambda r: _first(r).update(link="nowhere"), "root_tx.link: expected one of the links' names"),
        (lambda r: _first(r).update(axis=[0.0, 0.0, 0.0]), "root_tx.axis: expected a non-zero vector"),
        (lambda r: _first(r).update(position=[0.0, 1.0]), "root_tx.position: expected 3 finite numbers (m)"),
        (lambda r: r["links"][1].update(mass=-1.0), "links[1].mass: expected a number in [0, 10000] kg"),
        (lambda r: _first(r).update(strength=[1.0, "x"]), "root_tx.strength.positive: expected"),
    ],
)
def test_bad_values_get_the_checked_readers_messages(raw_frames: list[dict], edit, message: str) -> None:
    raw = _edit(raw_frames[0], edit)
    with pytest.raises(ResultFileError) as caught:
        read._frame(TableReader("r.json", raw, "frames[0].", ResultFileError))
    assert message in str(caught.value)
