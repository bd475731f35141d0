"""A family on disk: one body TOML per member (loadable by :func:`solver.io.scenario.bodies.load_body` and by a
scenario's
``[manikin] file = ...``) and the index ``family.toml`` beside them::

    [family]                       # how it was made
    source = "..."                 # the population's source
    sexes = ["male", "female"]
    coverage = 0.95                # of the (stature, mass) ellipse; points = 8, samples = 0, seed = 0

    [[members]]
    name = "male_c95_1"
    file = "male_c95_1.toml"       # relative to the folder
    sex = "male"
    role = "boundary"              # or "mean" or "sample"
    angle_deg = 0.0                # boundary only: angle on the standardised circle (0 = taller and heavier)
    [members.measurements]         # stature (m), mass (kg), then the extra measurements (m)
    stature = 1.8731
    mass = 101.23
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from ..errors import ModelError, UsageError
from ..io.files import read_toml, write_texts
from ..io.table_reader import TableReader
from ..io.toml_write import dumps_toml
from .family import ROLES, Member

INDEX = "family.toml"


@dataclass(frozen=True)
class Family:
    """A family read from ``folder``: the index's ``[family]`` table as ``info``, the ``members`` and each one's
    body file (``files[i]`` belongs to ``members[i]``)."""

    folder: Path
    info: dict
    members: tuple[Member, ...]
    files: tuple[Path, ...]


def check_family_folder(folder: str | Path) -> None:
    """Refuse an output folder that is a file or holds anything (a family is written whole, nothing overwritten)."""
    path = Path(folder)
    if path.exists() and not path.is_dir():
        raise UsageError(f"-o {path}: is a file, expected a new or empty folder")
    if path.is_dir() and any(path.iterdir()):
        raise UsageError(f"-o {path}: the folder is not empty, expected a new or empty folder")
    if path.is_dir() and not os.access(path, os.W_OK):
        raise UsageError(f"-o {path}: the folder is read-only")


def write_family(members: list[Member], folder: str | Path, info: dict) -> list[Path]:
    """Write each member's body TOML and the index (``info`` is its ``[family]`` table) into ``folder``, all or
    none; the paths written, the index last."""
    check_family_folder(folder)
    path = Path(folder)
    texts = [(path / f"{m.name}.toml", body_text(m, info)) for m in members]
    index = {"family": info, "members": [_entry(m) for m in members]}
    head = "# The index of the manikin family in this folder (written by `python -m solver family`).\n"
    texts.append((path / INDEX, head + dumps_toml(index, ModelError)))
    path.mkdir(parents=True, exist_ok=True)
    return write_texts(texts)


def body_text(member: Member, info: dict) -> str:
    """The body TOML of ``member`` (a human body with its measurements), with a comment on where it comes from."""
    if member.role == "boundary":
        what = f"boundary manikin at {member.angle:g} deg on the {info['coverage']:g} coverage ellipse"
    else:
        what = "mean manikin" if member.role == "mean" else f"random sample (seed {info['seed']})"
    body = {"kind": "human", "name": member.name, "sex": member.sex, "stature": member.stature, "mass": member.mass}
    body |= member.measurements
    body["source"] = f"{info['source']}; {what}; extra measurements: regression on stature and mass"
    head = (
        f"# {member.name}: {member.sex}, {what} of (stature, mass); see {INDEX} in this folder.\n"
        f"# Stature m, mass kg, the other lengths m. Written by `python -m solver family`.\n"
    )
    return head + dumps_toml({"body": body}, ModelError)


def _entry(member: Member) -> dict:
    entry = {"name": member.name, "file": f"{member.name}.toml", "sex": member.sex, "role": member.role}
    if member.angle is not None:
        entry["angle_deg"] = member.angle
    entry["measurements"] = {"stature": member.stature, "mass": member.mass} | member.measurements
    return entry


def read_family(folder: str | Path) -> Family:
    """The family in ``folder`` (its ``family.toml``); a ModelError line names the first problem."""
    index = Path(folder) / INDEX
    if not index.is_file():
        raise ModelError(f"{index}: not found (a family folder holds {INDEX}, see `python -m solver family`)")
    root = TableReader(index, read_toml(index, ModelError), error=ModelError)
    root.known({"family", "members"})
    members, files = [], []
    for t in root.table_list("members", non_empty=True):
        t.known({"name", "file", "sex", "role", "angle_deg", "measurements"})
        size = t.table("measurements")
        extra = {k: size.number(k, low=0.0) for k in size.data if k not in ("stature", "mass")}
        angle = t.number("angle_deg") if "angle_deg" in t.data else None
        sex = t.choice("sex", ("male", "female"), "a sex")
        role = t.choice("role", ROLES, "a role")
        members.append(Member(t.string("name"), sex, role, size.number("stature"), size.number("mass"), extra, angle))
        file = Path(t.string("file"))
        files.append(file if file.is_absolute() else index.parent / file)
        if not files[-1].is_file():
            raise t.fail("file", "an existing body file", str(file))
    return Family(Path(folder), dict(root.table("family").data), tuple(members), tuple(files))
