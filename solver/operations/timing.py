"""Timing like people: durations from MTM-1 and hand paths with a minimum-jerk profile. Units: s, m, kg.

Durations come from MTM-1 (Methods-Time Measurement; Maynard, Stegemerten & Schwab 1948, the MTM Association's
data card): 1 TMU = 0.036 s. A reach (R) or move (M) takes the card's time for its distance (inches, linear
between the card's rows, per inch beyond 30 in) and its case, which says the precision: reach A (to a fixed
place), B (to a single object whose place varies), C (to an object jumbled with others: a bin); move A (to a stop
or the other hand), B (to an approximate place), C (to an exact place: a fixture). A moved weight adds the card's
static TMU and multiplies by its dynamic factor. Walking is 15 TMU a pace (W-P), a bend and arise (B, AB) 29.0 +
31.9 TMU, an eye travel and focus (ET, EF) 15.2 TMU per unit of travel over distance (at most 20) + 7.3 TMU, a
grasp G1A 2.0 TMU, jumbled G4B 9.1 TMU, a release RL1 2.0 TMU.

A hand path follows the minimum-jerk profile (Flash & Hogan 1985): s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5 of
the way at tau = t / T, its peak speed 1.875 D / T at the middle.
"""

from __future__ import annotations

import numpy as np

TMU = 0.036  # s (1 TMU = 1e-5 h)
INCH = 0.0254  # m
# MTM-1 reach (R) and move (M) tables, TMU, by distance (in): columns case A, B, C
DISTANCES = np.array([0.75, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30])
REACH = np.array([
    [2.0, 2.0, 2.0], [2.5, 2.5, 3.6], [4.0, 4.0, 5.9], [5.3, 5.3, 7.3], [6.1, 6.4, 8.4], [6.5, 7.8, 9.4],
    [7.0, 8.6, 10.1], [7.4, 9.3, 10.8], [7.9, 10.1, 11.5], [8.3, 10.8, 12.2], [8.7, 11.5, 12.9], [9.6, 12.9, 14.2],
    [10.5, 14.4, 15.6], [11.4, 15.8, 17.0], [12.3, 17.2, 18.4], [13.1, 18.6, 19.8], [14.0, 20.1, 21.2],
    [14.9, 21.5, 22.5], [15.8, 22.9, 23.9], [16.7, 24.4, 25.3], [17.5, 25.8, 26.7],
])  # fmt: skip
MOVE = np.array([
    [2.0, 2.0, 2.0], [2.5, 2.9, 3.4], [3.6, 4.6, 5.2], [4.9, 5.7, 6.7], [6.1, 6.9, 8.0], [7.3, 8.0, 9.2],
    [8.1, 8.9, 10.3], [8.9, 9.7, 11.1], [9.7, 10.6, 11.8], [10.5, 11.5, 12.7], [11.3, 12.2, 13.5],
    [12.9, 13.4, 15.2], [14.4, 14.6, 16.9], [16.0, 15.8, 18.7], [17.6, 17.0, 20.4], [19.2, 18.2, 22.1],
    [20.8, 19.4, 23.8], [22.4, 20.6, 25.5], [24.0, 21.8, 27.3], [25.5, 23.1, 29.0], [27.1, 24.3, 30.7],
])  # fmt: skip
REACH_PER_INCH = np.array([0.4, 0.7, 0.7])  # TMU per inch beyond 30 in
MOVE_PER_INCH = np.array([0.8, 0.6, 0.85])
CASES = "ABC"
# MTM-1 weight allowance for a move: (up to lb, dynamic factor, static TMU)
WEIGHT = [(2.5, 1.00, 0.0), (7.5, 1.06, 2.2), (12.5, 1.11, 3.9), (17.5, 1.17, 5.6), (22.5, 1.22, 7.4),
          (27.5, 1.28, 9.1), (32.5, 1.33, 10.8), (37.5, 1.39, 12.5), (42.5, 1.44, 14.3), (47.5, 1.50, 16.0)]
POUND = 0.45359237  # kg
PACE_TMU = 15.0  # W-P
SIDE_STEP_TMU, SIDE_STEP_PER_CM = 34.1, 0.4  # SS-C2: a 30 cm side step, case II; per cm beyond
BEND_TMU = 29.0 + 31.9  # B + AB: down to below the knee and back up
GRASP_TMU, JUMBLED_GRASP_TMU, RELEASE_TMU = 2.0, 9.1, 2.0  # G1A, G4B, RL1
EYE_FOCUS_TMU, EYE_TRAVEL_TMU = 7.3, 15.2  # EF; ET per unit travel / distance, at most 20 TMU
BEND_HEIGHT = 0.5  # m: a hand target below this (about the knee) takes a bend and arise
MIN_DURATION = 0.1  # s: the shortest move (a few frames)


def _table_tmu(table: np.ndarray, per_inch: np.ndarray, distance: float, case: str) -> float:
    """The card's TMU for ``distance`` m in ``case`` (A, B or C): linear between rows, per inch beyond 30 in."""
    column = CASES.index(case)
    inches = max(distance / INCH, 0.0)
    if inches > DISTANCES[-1]:
        return float(table[-1, column] + per_inch[column] * (inches - DISTANCES[-1]))
    return float(np.interp(inches, DISTANCES, table[:, column]))


def reach_time(distance: float, case: str = "B") -> float:
    """MTM-1 reach R-``case`` over ``distance`` m, in s."""
    return max(_table_tmu(REACH, REACH_PER_INCH, distance, case) * TMU, MIN_DURATION)


def move_time(distance: float, case: str = "B", mass: float = 0.0, hands: int = 1) -> float:
    """MTM-1 move M-``case`` of ``mass`` kg over ``distance`` m, in s. The weight allowance is for the effective
    weight per hand: held in ``hands`` hands, each carries ``mass / hands``; beyond the card's 47.5 lb its last
    row."""
    factor, static = WEIGHT[-1][1:]
    for limit, f, s in WEIGHT:
        if mass / max(hands, 1) / POUND <= limit:
            factor, static = f, s
            break
    tmu = _table_tmu(MOVE, MOVE_PER_INCH, distance, case) * factor + static
    return max(tmu * TMU, MIN_DURATION)


def walk_time(paces: int) -> float:
    """MTM-1 walking, ``paces`` W-P, in s."""
    return paces * PACE_TMU * TMU


def side_step_time(distance: float) -> float:
    """MTM-1 side step, case II (the lagging leg on the floor before the next motion: a step-to side step with the
    weight shifted), both feet over ``distance`` m, in s: SS-C2 34.1 TMU for 30 cm, 0.4 TMU per cm beyond (the
    card says reach or move below 30 cm; the 30 cm time is kept there)."""
    return (SIDE_STEP_TMU + SIDE_STEP_PER_CM * max(distance * 100.0 - 30.0, 0.0)) * TMU


def eye_time(travel: float, distance: float) -> float:
    """MTM-1 eye travel (``travel`` m between the points looked at, ``distance`` m from the eyes) and focus, s."""
    et = min(EYE_TRAVEL_TMU * travel / max(distance, 1e-3), 20.0)
    return (et + EYE_FOCUS_TMU) * TMU


def min_jerk(tau: np.ndarray | float) -> np.ndarray | float:
    """Share of the way done at ``tau`` = t / T in [0, 1] on a minimum-jerk path (Flash & Hogan 1985)."""
    t = np.clip(tau, 0.0, 1.0)
    return t**3 * (10.0 - 15.0 * t + 6.0 * t * t)


def min_jerk_speed(tau: np.ndarray | float, distance: float, duration: float) -> np.ndarray | float:
    """Speed (m/s) at ``tau`` along a minimum-jerk path of ``distance`` m taking ``duration`` s."""
    t = np.clip(tau, 0.0, 1.0)
    return distance / duration * 30.0 * t * t * (1.0 - t) ** 2
