"""The manikin behind a result: joint strengths and the standard working area (thesis §6.1.2) of its own body.

A result file names its scenario (top-level ``scenario``); the scenario's ``[manikin]`` table names a preset or a
body file, which :func:`solver.io.scenario.bodies.load_body` builds. Strengths come from the result itself when its
joints
carry ``strength`` ([negative, positive] capacity, N*m, null = unlimited), else from that model
(:attr:`solver.body.model.Model.strength`, sources in :mod:`solver.body.humans.anthropometry`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np

from ..body.model import Model
from ..body.spatial import cross, length  # np.cross's arithmetic, without its overhead on small arrays
from ..errors import ManikinError, UsageError
from ..io.result.frame import Frame
from ..io.scenario.bodies import is_body_file, load_preset

_UP = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class WorkingArea:
    """Thesis §6.1.2 workspace box in the feet frame: x to the manikin's left, y forward, z up from the floor (m).

    Bounds (Delfs 2012 §6.1.2, after its ref. [4]): upper at the shoulder (glenohumeral joint height), lower at the
    knuckles with the arms relaxed at the sides, left/right at the elbows with both arms stretched out sideways,
    back at the body's vertical line, front at the knuckles with the arms stretched forward. All from the
    manikin's own zero pose (standing upright, arms hanging).
    """

    x_half: float
    y_back: float
    y_front: float
    z_low: float
    z_high: float

    def outside_by(self, p: np.ndarray) -> float:
        """Distance (m) of a feet-frame point outside the box; 0 inside."""
        lo, hi = self._bounds
        return length(np.maximum(lo - p, 0.0) + np.maximum(p - hi, 0.0))

    @cached_property
    def _bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """The low and high corners (m), made once: every frame of a motion asks (the box is frozen)."""
        return np.array([-self.x_half, self.y_back, self.z_low]), np.array([self.x_half, self.y_front, self.z_high])

    def as_dict(self) -> dict:
        return dict(x=[-self.x_half, self.x_half], y=[self.y_back, self.y_front], z=[self.z_low, self.z_high])

    def rounded(self) -> dict:
        """:meth:`as_dict` rounded to mm, as each frame's worksheet shows it (a new dict; the numbers made once)."""
        return {k: list(b) for k, b in self._rounded.items()}

    @cached_property
    def _rounded(self) -> dict[str, list[float]]:
        return {k: [round(v, 3) for v in b] for k, b in self.as_dict().items()}


def feet_frame(tcp_position: dict, tcp_rotation: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """(origin, forward, left) of the feet frame: origin between the sole centres (on the floor), forward the mean
    horizontal heading of the feet (a foot faces its TCP's -y, as in the zero pose), left = z x forward."""
    if "foot_l" not in tcp_position or "foot_r" not in tcp_position:
        return None
    origin = 0.5 * (tcp_position["foot_l"] + tcp_position["foot_r"])
    origin = np.array([origin[0], origin[1], 0.0])
    heading = -(tcp_rotation["foot_l"][:, 1] + tcp_rotation["foot_r"][:, 1])
    heading[2] = 0.0
    norm = length(heading)
    forward = heading / norm if norm > 1e-9 else np.array([0.0, -1.0, 0.0])
    left = cross(_UP, forward)
    return origin, forward, left


def to_feet(p: np.ndarray, frame: tuple[np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
    """World point -> feet frame (left, forward, up), m."""
    origin, forward, left = frame
    d = p - origin
    return np.array([d @ left, d @ forward, p[2]])


def working_area(model: Model) -> WorkingArea | None:
    """The §6.1.2 box of ``model`` from its zero pose; None if it is not the human body."""
    need = ("shoulder_r_flexion", "elbow_r_flexion", "wrist_r_flexion", "l5_rx")
    if not all(n in model.joint_names for n in need) or not {"knuckles_r", "foot_l", "foot_r"} <= set(model.tcps):
        return None
    kin = model.forward(model.zero_pose())
    pos = {n: kin.position[model.joint_index(n)] for n in need}
    tcp_p, tcp_r = {}, {}
    for name in ("knuckles_r", "foot_l", "foot_r"):
        tcp_r[name], tcp_p[name] = kin.tcp_frame(model.tcps[name])
    frame = feet_frame(tcp_p, tcp_r)
    gh, elbow, wrist = (to_feet(pos[n], frame) for n in need[:3])
    knuckles = to_feet(tcp_p["knuckles_r"], frame)
    upper, fore, hand = (float(np.linalg.norm(a - b)) for a, b in ((elbow, gh), (wrist, elbow), (knuckles, wrist)))
    return WorkingArea(
        x_half=abs(gh[0]) + upper,
        y_back=float(to_feet(pos["l5_rx"], frame)[1]),
        y_front=float(gh[1]) + upper + fore + hand,
        z_low=float(knuckles[2]),
        z_high=float(gh[2]),
    )


def _scenario_manikin(scenario: Path, result_dir: Path) -> Model:
    """The manikin of the scenario a result names (relative paths: from the working or the result's folder)."""
    candidates = [scenario] if scenario.is_absolute() else [scenario, result_dir / scenario]
    found = next((c for c in candidates if c.is_file()), None)
    if found is None:
        raise ManikinError(f"scenario file {str(scenario)!r} not found")
    # imported here: the scenario reader loads scipy, and the Blender layer imports this package when it enables
    from ..io.scenario.read import scenario_manikin

    return scenario_manikin(found)


def resolve_model(manikin: str | None, scenario: str | None, result_dir: Path) -> tuple[Model | None, str]:
    """The body behind a result: ``manikin`` (preset name or body TOML) if given, else the scenario's manikin.

    Returns (model or None, a note saying where it came from or why there is none).
    """
    if manikin:
        try:
            model = load_preset(manikin)
        except ManikinError as exc:  # asked for by name: an error, not a note
            raise UsageError(f"manikin {manikin!r}: {exc}") from None
        return model, f"{'body file' if is_body_file(manikin) else 'preset'} {manikin}"
    try:
        if scenario:
            return _scenario_manikin(Path(scenario), result_dir), f"manikin of scenario {scenario}"
    except ManikinError as exc:
        return None, f"no manikin: {exc}"
    return None, "no manikin: the result names no scenario and no --manikin was given"


def check_fits(model: Model, frame: Frame, name: str) -> None:
    """Refuse a manikin (asked for as ``name``) that lacks joints of the result's frame: another kind of body."""
    missing = [j for j in frame.joint_names if j not in set(model.joint_names)]
    if missing:
        raise UsageError(
            f"manikin {name!r}: not the body of this result ({len(missing)} of its {len(frame.joint_names)} joints, "
            f"e.g. {missing[0]!r}, are not joints of {model.name}); give a manikin of the same kind"
        )


def strengths(frame: Frame, model: Model | None) -> tuple[np.ndarray, str]:
    """(n, 2) capacity (negative, positive moments), N*m, NaN where unknown, and where it came from."""
    n = len(frame.joint_names)
    out = np.full((n, 2), np.nan)
    if frame.joint_strength is not None:
        return frame.joint_strength.copy(), "result file (joints' strength)"
    if model is None:
        return out, "unknown (no manikin)"
    names = dict(zip(model.joint_names, model.strength, strict=True))
    missing = 0
    for i, name in enumerate(frame.joint_names):
        if name in names:
            out[i] = names[name]
        else:
            missing += 1
    note = f"model {model.name}" + (f" ({missing} joints of the result not in the model)" if missing else "")
    return out, note
