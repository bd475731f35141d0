"""What an evaluation needs beyond the result file: task facts no pose can tell (frequency, coupling, ...).

Thresholds marked PROJECT DEFAULT below are this project's reading of words such as "twisted" or "neutral" in
the observational methods, which give no number; they are not published values.
"""

from __future__ import annotations

from dataclasses import dataclass

ACTIVITIES = ("intermittent", "static", "repeated")
COUPLINGS = ("good", "fair", "poor", "unacceptable")
DURATIONS = ("short", "moderate", "long")

# PROJECT DEFAULTS (estimates, see the module docstring)
TWIST_DEG = 10.0  # trunk / neck "twisted" or "side bent" beyond this; EN 1005-4 calls >= 10 deg clearly visible
NEUTRAL_DEG = 5.0  # a wrist within +-5 deg counts as "neutral" / "not bent from the midline"
ABDUCTED_DEG = 20.0  # upper arm "abducted" beyond 20 deg of sideways elevation
SHOULDER_RAISED_DEG = 10.0  # shoulder "raised": clavicle elevation beyond 10 deg
TWIST_END_SHARE = 0.75  # wrist twist "at or near the end of range": forearm rotation beyond 75 % of its range
FEATHER_SHARE = 0.1  # a foot carrying less than 10 % of the weight is "feather weight bearing", not standing on it
EVEN_WEIGHT_SHARE = 1.0 / 3.0  # weight "evenly" on both feet: neither foot carries less than a third
OUT_TO_SIDE_M = 0.05  # lower arm "out to the side": wrist more than 5 cm outside the shoulder joint's line
KNEE_BENT_DEG = 30.0  # OWAS "knee bent" beyond 30 deg of knee flexion (REBA's first knee band starts there)
OWAS_BENT_DEG = 20.0  # OWAS back "bent" beyond 20 deg of trunk flexion (RULA/REBA's first bend band ends there)


@dataclass(frozen=True)
class ErgoOptions:
    """Task facts for one evaluation (units: kg, lifts/min, m)."""

    load_mass: float | None = None  # kg handled; default: the result's loads on the hand TCPs
    activity: str = "intermittent"  # RULA muscle use / force: intermittent, static (> 1 min) or repeated
    shock: bool = False  # sudden or jerky forces (RULA force 3, REBA +1)
    coupling: str = "fair"  # hand coupling: NIOSH good/fair/poor, REBA good/fair/poor/unacceptable
    frequency: float = 1.0  # NIOSH lifts per minute
    duration: str = "short"  # NIOSH: short (<= 1 h), moderate (1-2 h), long (2-8 h)
    destination_control: bool = False  # NIOSH: significant control at the destination (RWL there too)
    travel: float | None = None  # NIOSH vertical travel D (m) when origin and destination are the same frame
    origin: int | None = None  # NIOSH origin frame number (default: the first frame)
    destination: int | None = None  # NIOSH destination frame number (default: the last frame)
    manikin: str | None = None  # preset name or body TOML for strengths and the working area

    def check(self) -> None:
        """Raise ValueError naming the bad option."""
        if self.activity not in ACTIVITIES:
            raise ValueError(f"activity must be one of {', '.join(ACTIVITIES)}, got {self.activity!r}")
        if self.coupling not in COUPLINGS:
            raise ValueError(f"coupling must be one of {', '.join(COUPLINGS)}, got {self.coupling!r}")
        if self.duration not in DURATIONS:
            raise ValueError(f"duration must be one of {', '.join(DURATIONS)}, got {self.duration!r}")
        if not 0.0 <= self.frequency <= 100.0:
            raise ValueError(f"frequency must be in [0, 100] lifts/min, got {self.frequency}")
        if self.load_mass is not None and not 0.0 <= self.load_mass <= 1000.0:
            raise ValueError(f"load mass must be in [0, 1000] kg, got {self.load_mass}")
        if self.travel is not None and not 0.0 <= self.travel <= 10.0:
            raise ValueError(f"travel must be in [0, 10] m, got {self.travel}")
