"""The iteration's tuning knobs in one frozen, documented value (how they were measured: docs/TUNING.md)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Tuning:
    """How the method works, fixed once by measurement; what a user chooses per solve is in ``SolverOptions``.

    Steps and bounds are in scaled variables (1 = half a joint's range, forces / body weight); errors in
    tolerances (1 = a row at its tolerance).
    """

    # The least-squares step
    max_damping: float = 1e-3  # Tikhonov damping, x largest singular value: matters only near singularities
    max_step: float = 1.0  # trust region: largest 2-norm of a task step
    max_comfort_step: float = 0.5  # largest entry of a comfort step
    clamping_rounds: int = 10  # re-solves without the variables a step pushed past a bound
    hold_overshoot: float = 0.5  # scaled rows: a released contact row the step would push deeper than this is held
    fraction_near: float = 0.02  # a joint closer than this to its limit may be saturated right at it, else halfway
    force_barrier: float = 0.05  # log-barrier curvature of a contact edge weight: keeps light edges off zero
    force_floor: float = 0.01  # edge weight (/ body weight) below which the barrier stops growing
    # The comfort metric and its quasi-Newton memory
    initial_mu: float = 0.1  # comfort metric damping at the start, x the mean curvature
    mu_factor: float = 4.0  # mu shrinks/grows by this when the comfort model predicted well/badly
    memory: int = 6  # curvature pairs kept by the limited-memory BFGS model
    # Trials and their acceptance
    comfort_slack: float = 10.0  # within this error a step is "near" and carries comfort
    least_contact_share: float = 0.05  # a step cut short of a new contact to less than this share is not cut
    penalty_margin: float = 2.0  # the exact-penalty merit's weight of sum |error|: this x the largest multiplier
    hopeless: float = 5.0  # a near trial worse than this x comfort_slack is halved without a correction
    correct_accepted: bool = True  # near: correct a comfort trial the merit accepts as it is (False: keep it)
    max_turn: float = 0.3  # rad: largest joint rotation of a step far from the constraints
    max_slide: float = 0.3  # m: the same for a prismatic joint
    max_rejected: int = 6  # steps rejected in a row before a phase gives up
    near_comfort_tries: int = 2  # near the constraints: halvings of task + comfort before the task part alone
    far_comfort_tries: int = 1  # far from them: comfort rides along a full step only
    far_comfort_check: bool = True  # ... and only if comfort ends no worse than predicted (False: if the error falls)
    task_tries: int = 5  # backtracking tries of the task part alone (one fewer after comfort tries near)
    comfort_shrink: float = 1.0  # < 1: after comfort was given up, cap the next comfort part at this x the rejected one
    comfort_retry: float = 0.0  # > 0: near, a rejected comfort try keeps its task part and scales comfort by this
    task_first: bool = False  # after comfort was given up, try the task part alone first in the next iteration
    task_first_far: bool = False  # the same only far from the constraints (comfort rides along no step then)
    # Stopping
    final_gain: float = 2.0  # a full feasible comfort step predicted to gain < this x tolerance ends the phase
    hover_limit: int = 12  # comfort iterations just outside the constraints before the restoring phase
    hover_gain: float = 1e3  # ... not counting those whose step gained more than this x tolerance
    stagnation_window: int = 10  # iterations over which the error must fall (far from the constraints)
    restore_stagnation_window: int = 3  # the same for the sum of squares when restoring without comfort
    stagnation_gain: float = 0.02  # the fraction by which it must fall over that window
    polish_iterations: int = 20  # iterations kept back for the restoring phase
    # Restarts
    restart_near: float = 0.05  # a joint within this fraction of its range from a limit is restarted
    restart_at: float = 0.25  # ... at this fraction of its range from the other limit


TUNING = Tuning()
