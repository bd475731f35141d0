"""The study file (TOML): which manikins, which scenarios with which parameters, what to record
(docs/tutorials/study.md). Every problem is one ScenarioError line naming the study file and the key.

::

    manikins = ["female_5", "male_95", "bodies/tall.toml", "family_95/"]   # presets, body files, family folders
    # a family folder written by `python -m solver family` has an index (family.toml): its rows then say each
    # member's role, sex and measurements (columns role, sex, stature_m, mass_kg, <measurement>_m)

    [study]
    name = "box height"   # optional
    seed = 0              # base of every run's seed
    repeats = 1           # runs per combination, each with its own seed
    start_jitter = 0.0    # rad: spread of a seeded random change of the start pose (0: the scenario's start)
    record = ["shortfall", "rula", "reba", "l4_l5", "strength", "niosh"]   # default: all (.groups.record())

    [[scenarios]]
    file = "../presets/scenarios/box_lift.toml"   # relative to the study file
    name = "lift"            # default: the file's stem
    keep_manikin = false     # true: the scenario's own [manikin], not the study's manikins
    job = "../presets/jobs/box_lift_job.toml"   # optional: rate each run's motion as this job ([work], [load];
    # its [motion] is not used): the job columns (.job_columns)
    ergonomics = { frequency = 2.0, duration = "moderate" }   # NIOSH / RULA task facts (ErgoOptions)
    with = { carried = { size = [0.35, 0.26, 0.24], tcps = ["hand_r", "hand_l"] } }   # tables put into the file's
    # data (one of the same name replaced), e.g. the box the hands hold, before the parameters are applied
    [scenarios.parameters.box_height]
    values = [0.35, 0.45, 0.55]
    set = ["targets.hand_r.position[2]", "targets.hand_l.position[2]"]   # key paths (solver/study/keypath.py)
    # or add = [...]: each value is added to the file's number there (an offset)

    [envelope]                # reach envelopes of every manikin, with or instead of [[scenarios]] (.envelope_spec)
    load_kg = [0.0, 10.0]
    feet = ["planted", "step"]
"""

from __future__ import annotations

import functools
import hashlib
import json
import re
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..body.model import Model
from ..ergonomics import ErgoOptions
from ..errors import ManikinError, ScenarioError
from ..io.files import read_toml
from ..io.scenario.bodies import MANIKINS_DIR as PRESET_BODIES
from ..io.scenario.bodies import body_from_dict, list_presets
from ..io.scenario.read import scenario_from_dict
from ..io.table_reader import TableReader, is_number
from ..population.family_files import INDEX, read_family
from . import keypath
from .envelope_spec import EnvelopeStudy, load_envelope
from .groups import record as recordable
from .job_columns import GROUP as JOB

if TYPE_CHECKING:
    from ..job.spec import Job
    from ..population.family import Member

NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
ERGO_KEYS = tuple(f.name for f in fields(ErgoOptions) if f.name != "manikin")  # the study sets the manikin
MAX_REPEATS, MAX_JITTER = 1000, 1.0  # runs per combination; rad


@dataclass(frozen=True)
class Manikin:
    """A study's manikin: its row name, a preset name or an absolute body file, the body's tables (run id) and,
    for a member of a family folder with an index, its ``member`` facts (row columns: :func:`member_facts`)."""

    name: str
    preset: str | None
    file: Path | None
    body: dict
    member: dict = field(default_factory=dict)

    @functools.cached_property
    def key(self) -> str:
        """A hash of the body's tables: the same body, the same key (once: the tables are not changed after they are
        read, and a worker asks every run)."""
        return digest(self.body)

    def table(self) -> dict:
        """The scenario's [manikin] table that puts this manikin in it."""
        return {"preset": self.preset} if self.preset is not None else {"file": str(self.file)}

    def model(self) -> Model:
        """The body built (as the scenario's [manikin] table would build it)."""
        where = PRESET_BODIES / f"{self.preset}.toml" if self.preset else self.file
        return body_from_dict(self.body, str(where), self.preset or self.file.stem)


def member_facts(member: Member) -> dict:
    """A family member's row columns (a :class:`solver.population.Member`): role, sex, stature (m), mass (kg) and
    each extra measurement (m)."""
    facts = dict(role=member.role, sex=member.sex, stature_m=member.stature, mass_kg=member.mass)
    return facts | {f"{key}_m": value for key, value in member.measurements.items()}


def member_columns(study: Study) -> list[str]:
    """The member columns of the study's manikins, in order of first appearance (none without a family index)."""
    return list(dict.fromkeys(key for m in study.manikins for key in m.member))


def digest(value: Any) -> str:
    """A stable hex hash of JSON-able ``value`` (keys sorted)."""
    text = json.dumps(value, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


@dataclass(frozen=True)
class Parameter:
    """A named parameter: its values and the key paths each value is set at (``set``) or added to (``add``)."""

    name: str
    values: tuple
    set: tuple[str, ...]
    add: tuple[str, ...]


@dataclass(frozen=True)
class StudyScenario:
    """One [[scenarios]] entry: the scenario file's tables, its parameters and task facts."""

    name: str
    path: Path
    data: dict
    parameters: tuple[Parameter, ...]
    keep_manikin: bool
    ergonomics: dict
    job: Job | None = None  # the job each run's motion is rated as (its [work] and [load])


@dataclass(frozen=True)
class Study:
    """A parsed study file (see the module docstring)."""

    path: Path
    name: str
    manikins: tuple[Manikin, ...]
    scenarios: tuple[StudyScenario, ...]
    record: tuple[str, ...]
    seed: int
    repeats: int
    start_jitter: float
    envelope: EnvelopeStudy | None = None  # [envelope]: reach envelopes of every manikin (.envelope_spec)


def load_study(path: str | Path) -> Study:
    """Read and check a study file; every problem is one ScenarioError line."""
    path = Path(path)
    root = TableReader(path, read_toml(path, ScenarioError), error=ScenarioError)
    root.known({"manikins", "study", "scenarios", "envelope"})
    head = root.table("study")
    if "manikins" in head.data:  # TOML puts every key after a [table] header into that table
        raise head.fail("manikins", "manikins = [...] at the top of the file, before [study] (unknown key here)")
    head.known({"name", "seed", "repeats", "start_jitter", "record"})
    groups = recordable()
    record = head.get("record", list(groups))
    if not isinstance(record, list) or not all(r in groups for r in record):
        raise head.fail("record", "a list of " + ", ".join(groups), record)
    checked: set[str] = set()  # the scenario files found valid (a study may name one file many times)
    if "scenarios" not in root.data and "envelope" not in root.data:
        raise root.fail("scenarios", "a non-empty array of tables [[scenarios]], or an [envelope] table")
    listed = root.table_list("scenarios", non_empty="envelope" not in root.data)
    scenarios = tuple(_scenario(t, path.parent, checked) for t in listed)
    envelope = load_envelope(root.table("envelope")) if "envelope" in root.data else None
    names = [s.name for s in scenarios] + ([envelope.name] if envelope else [])
    _unique(root, "scenarios", names, "scenario names (give each a name; the [envelope]'s name is one too)")
    manikins = _manikins(root, path.parent)
    if envelope is not None and not manikins:
        raise root.fail("manikins", "at least one manikin for the [envelope] (presets, body files or a family)")
    return Study(
        path=path,
        name=head.string("name", path.stem),
        manikins=manikins,
        scenarios=scenarios,
        record=tuple(r for r in groups if r in record and (r != JOB or any(s.job for s in scenarios))),
        seed=head.integer("seed", 0, 0, 2**31 - 1),
        repeats=head.integer("repeats", 1, 1, MAX_REPEATS),
        start_jitter=head.number("start_jitter", 0.0, 0.0, MAX_JITTER, "rad"),
        envelope=envelope,
    )


def _unique(t: TableReader, key: str, names: list[str], what: str) -> None:
    seen = {n for n in names if names.count(n) > 1}
    if seen:
        raise t.fail(key, f"distinct {what}", sorted(seen)[0] + " (twice)")


def _manikins(root: TableReader, here: Path) -> tuple[Manikin, ...]:
    """``manikins``: names of presets, body files or family folders (strings), or tables {preset|file|family}."""
    items = root.get("manikins", [])
    if not isinstance(items, list):
        raise root.fail("manikins", "a list of preset names, body files or family folders", items)
    out: list[Manikin] = []
    for i, item in enumerate(items):
        where = TableReader(root.path, {}, f"manikins[{i}]", ScenarioError)
        if isinstance(item, str) and item:
            out += _resolve(where, "", item, here, None)
        elif isinstance(item, dict):
            t = TableReader(root.path, item, f"manikins[{i}].", ScenarioError)
            t.known({"preset", "file", "family", "name"})
            given = [k for k in ("preset", "file", "family") if k in t.data]
            if len(given) != 1:
                raise t.fail("preset", 'exactly one of preset = "...", file = "body.toml" or family = "folder"')
            name = t.string("name") if "name" in t.data else None
            out += _resolve(where, given[0], t.string(given[0]), here, name)
        else:
            raise where.fail("", "a preset name, a body file, a family folder or a table {preset|file|family}", item)
    _unique(root, "manikins", [m.name for m in out], 'manikin names (a table with name = "..." renames one)')
    return tuple(out)


def _resolve(where: TableReader, kind: str, text: str, here: Path, name: str | None) -> list[Manikin]:
    """The manikins one entry names: a preset, a body file, or every body file of a family folder (its index,
    a TOML without [body], is skipped)."""
    path = Path(text) if Path(text).is_absolute() else here / text
    if kind == "preset" or (not kind and text in list_presets() and not path.exists()):
        if text not in list_presets():
            raise where.fail("", "a manikin preset: " + ", ".join(list_presets()), text)
        return [_manikin(where, name or text, text, PRESET_BODIES / f"{text}.toml")]
    if kind != "file" and path.is_dir():
        bodies = [p for p in sorted(path.glob("*.toml")) if "body" in read_toml(p, ScenarioError)]
        if not bodies:
            raise where.fail("", f"a family folder with body TOML files ({path} has none)", text)
        members = _members(where, path, text)
        return [_manikin(where, f"{name or path.name}/{_body_name(p)}", None, p, members.get(p.resolve(), {}))
                for p in bodies]  # fmt: skip
    if kind == "family" or not path.is_file():
        what = "a family folder" if kind == "family" else "a preset name, a body file or a family folder"
        raise where.fail("", f"{what} (not found: {path})", text)
    return [_manikin(where, name or _body_name(path), None, path)]


def _members(where: TableReader, folder: Path, text: str) -> dict[Path, dict]:
    """The row facts of each body file a family folder's index lists ({} without an index); an index that does
    not read is one line naming it."""
    if not (folder / INDEX).is_file():
        return {}
    try:
        family = read_family(folder)
    except ManikinError as exc:
        raise where.fail("", f"a family folder whose {INDEX} reads ({exc})", text) from None
    return {file.resolve(): member_facts(m) for m, file in zip(family.members, family.files, strict=True)}


def _body_name(path: Path) -> str:
    body = read_toml(path, ScenarioError).get("body", {})
    name = body.get("name") if isinstance(body, dict) else None
    return name if isinstance(name, str) and name else path.stem


def _manikin(where: TableReader, name: str, preset: str | None, path: Path, member: dict | None = None) -> Manikin:
    """Check the body builds (one line naming it if not) and keep its tables for the run ids."""
    data = read_toml(path, ScenarioError)
    try:
        body_from_dict(data, str(path), name)
    except ManikinError as exc:
        raise where.fail("", f"a body that builds ({exc})") from None
    return Manikin(name, preset, None if preset else path.resolve(), data, member or {})


def _scenario(t: TableReader, here: Path, checked: set[str]) -> StudyScenario:
    t.known({"file", "name", "keep_manikin", "ergonomics", "parameters", "with", "job"})
    t.required("file")
    path = Path(t.string("file"))
    path = (path if path.is_absolute() else here / path).resolve()
    data = read_toml(path, ScenarioError)
    extra = t.table("with")
    for key, value in extra.data.items():
        if not isinstance(value, dict):
            raise extra.fail(key, "a table (a scenario table such as carried or floor)", value)
    data = {**data, **extra.data}
    if digest([str(path), data]) not in checked:
        try:
            scenario_from_dict(data, path)  # the file as it is must be a scenario; a parameter's value may still fail
        except ManikinError as exc:
            raise t.fail("with" if extra.data else "file", f"a valid scenario ({exc})") from None
        checked.add(digest([str(path), data]))
    ergo = t.table("ergonomics")
    ergo.known(ERGO_KEYS)
    try:
        ErgoOptions(**ergo.data).check()
    except (TypeError, ValueError) as exc:
        raise ergo.fail("", f"ergonomics options ({exc})") from None
    named = t.named_tables("parameters")
    parameters = tuple(_parameter(name, p, data) for name, p in named.items())
    return StudyScenario(t.string("name", path.stem), path, data, parameters, t.boolean("keep_manikin", False),
                         dict(ergo.data), _job(t, here) if "job" in t.data else None)  # fmt: skip


def _job(t: TableReader, here: Path) -> Job:
    """The job file named by ``job`` (relative to the study file), read by the job command's reader."""
    from ..job.spec import read_job

    path = Path(t.string("job"))
    try:
        return read_job(path if path.is_absolute() else here / path)
    except ManikinError as exc:
        raise t.fail("job", f"a valid job file ({exc})") from None


def _parameter(name: str, t: TableReader, data: dict) -> Parameter:
    """One [scenarios.parameters.NAME] table: values and the key paths they go to, each path checked in ``data``."""
    if not NAME.fullmatch(name):
        raise t.fail("", "a parameter name of letters, digits and _ (not starting with a digit)", name)
    t.known({"values", "set", "add"})
    values = t.get("values")
    if not isinstance(values, list) or not values or not all(_plain(v) for v in values):
        raise t.fail("values", "a non-empty list of finite numbers, booleans, strings or lists of them", values)
    if len({repr(v) for v in values}) != len(values):
        raise t.fail("values", "distinct values", values)
    paths = {}
    for key in ("set", "add"):
        paths[key] = t.get(key, [])
        if not isinstance(paths[key], list) or not all(isinstance(p, str) for p in paths[key]):
            raise t.fail(key, "a list of key paths such as 'targets.hand_r.position[2]'", paths[key])
        for i, p in enumerate(paths[key]):
            try:
                keypath.check(data, p, values, add=key == "add")
            except ValueError as exc:
                raise t.fail(f"{key}[{i}]", f"a key path into the scenario ({p}: {exc})") from None
    if not paths["set"] and not paths["add"]:
        raise t.fail("set", "at least one key path in set = [...] or add = [...]")
    return Parameter(name, tuple(values), tuple(paths["set"]), tuple(paths["add"]))


def _plain(value) -> bool:
    """A parameter value: a finite number, a boolean, a string or a list of them (no table, no NaN)."""
    if isinstance(value, list):
        return all(_plain(v) for v in value)
    return isinstance(value, bool | str) or is_number(value)
