"""Velocity controller: surge speed, yaw rate and (fully actuated vessels) sway speed → τ = (X, Y, N).

Per axis (x = u, v or r at the CoM, body FLU; m = mass or yaw inertia):

    τ = m a_ref + [C(ν_ref)ν_ref + D(ν_ref)ν_ref]_axis + Kp e + ∫ Ki e dt,   e = x_ref - x

* Reference model: the command passes a critically damped 2nd-order filter (bandwidth ω_ref) with
  acceleration and velocity limits, giving x_ref and a_ref (smooth, physically attainable).
* Feed-forward from the vessel's own model (`usvsim.control.plant`): inertia × reference acceleration,
  rigid-body Coriolis and the drag D(ν_ref)ν_ref, so the feedback only corrects model errors.
* Feedback, λ-tuning (IMC pole placement) on the linearized model m ẋ + d x = τ: Kp = λ m and
  Ki = λ d, with d = ∂(Dν)/∂x re-evaluated at the reference every update (gain scheduling), so the PI
  zero cancels the plant pole -d/m and the error dynamics are first order at -λ. Where the plant pole is
  slower than λ/4, d is floored at λ m / 4, making the loop critically damped at λ/2.
  λ defaults to min(2, 1/(4 T_act)) rad/s, T_act the slowest thruster time constant (thrust or azimuth servo).
* Anti-windup by back-calculation: after allocation, each integrator moves toward the τ the thrusters
  actually deliver (`report_achieved`), with tracking rate λ; integrators are also clamped to capacity.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from usvsim.control.layout import ThrusterLayout
from usvsim.control.plant import PlantModel
from usvsim.control.velocity_kernels import (
    A_MAX,
    A_REF,
    ACTIVE,
    AW_RATE,
    I_MAX,
    INERTIA,
    INTEG,
    KI,
    KP,
    LAMBDA,
    N_AXIS,
    N_STATE,
    V_MAX,
    W_REF,
    X_REF,
    back_calculate,
    velocity_step,
)  # fmt: skip
from usvsim.core.errors import require_finite

AXES = ("surge", "sway", "yaw")


@dataclass(frozen=True)
class AxisTuning:
    """Overrides for one axis; None = derived from the vessel. Units per axis: surge/sway in m/s, N;
    yaw in rad/s, N m. `ki` set fixes the integral gain (no scheduling)."""

    bandwidth_rad_s: float | None = None
    kp: float | None = None
    ki: float | None = None
    reference_bandwidth_rad_s: float | None = None
    max_acceleration: float | None = None
    max_velocity: float | None = None

    def __post_init__(self):
        # checked as the scenario keys are: a NaN gain left the boat still under any command, a negative bandwidth
        # drove it backwards (-1.18 m/s for +1 m/s), and max_velocity=0 was taken for "derive it"
        for name, value in vars(self).items():
            if value is not None:
                require_finite("AxisTuning", name, value, zero_ok=name in ("kp", "ki"), note=" (None: derived)")


def actuator_time_constant(thrusters) -> float:
    """Slowest time constant of a vessel's thrusters (thrust lag or azimuth servo), s."""
    taus = [max(t.time_constant_s, t.azimuth.time_constant_s if t.azimuth else 0.0) for t in thrusters]
    return max(taus, default=0.1)


def design_gains(plant: PlantModel, layout: ThrusterLayout, actuator_tau_s: float = 0.2,
                 tuning: tuple[AxisTuning, AxisTuning, AxisTuning] | None = None) -> np.ndarray:  # fmt: skip
    """(3, N_AXIS) parameter table of the velocity controller (see the module docstring for the design)."""
    tuning = tuning or (AxisTuning(), AxisTuning(), AxisTuning())
    cap = layout.capacity()
    active = np.array([cap[0] > 0, layout.is_fully_actuated(), cap[2] > 0], dtype=float)
    p = np.zeros((3, N_AXIS))
    for k, (m, t) in enumerate(zip(plant.inertia_diag, tuning, strict=True)):
        lam = t.bandwidth_rad_s or min(2.0, 1.0 / (4.0 * actuator_tau_s))
        p[k, INERTIA], p[k, LAMBDA], p[k, ACTIVE] = m, lam, active[k]
        p[k, KP] = t.kp if t.kp is not None else lam * m
        p[k, KI] = t.ki if t.ki is not None else -1.0
        p[k, W_REF] = t.reference_bandwidth_rad_s or 1.0
        p[k, A_MAX] = t.max_acceleration or max(0.5 * cap[k] / m, 1e-6)
        p[k, V_MAX] = t.max_velocity or plant.max_speed(k, cap[k])
        p[k, I_MAX] = max(cap[k], 1e-9)
        p[k, AW_RATE] = lam
    return p


class VelocityController:
    """update(ν, ν_cmd, dt) → τ. ν, ν_cmd: (u [m/s], v [m/s], r [rad/s]) at the CoM, body FLU; τ (X, Y, N)
    about the CoM. State (reference model, integrators) is explicit in `state`; `reset()` clears it."""

    def __init__(self, plant: PlantModel, gains: np.ndarray, coriolis_feedforward: bool = True):
        self.plant = plant
        self.gains = np.ascontiguousarray(gains, dtype=float)
        self.coriolis = bool(coriolis_feedforward)
        self.state = np.zeros(N_STATE)

    @classmethod
    def design(cls, plant: PlantModel, layout: ThrusterLayout, actuator_tau_s: float = 0.2,
               tuning=None, coriolis_feedforward: bool = True) -> VelocityController:  # fmt: skip
        return cls(plant, design_gains(plant, layout, actuator_tau_s, tuning), coriolis_feedforward)

    def reset(self) -> None:
        """Restart: the reference starts at the next measured velocity, integrators at zero."""
        self.state[:] = 0.0

    def update(self, nu, nu_cmd, dt: float) -> np.ndarray:
        tau = np.empty(3)
        velocity_step(self.gains, self.plant.drag, self.state, np.asarray(nu, dtype=float),
                      np.asarray(nu_cmd, dtype=float), float(dt), self.coriolis, tau)  # fmt: skip
        return tau

    def report_achieved(self, tau_achieved, dt: float) -> None:
        """Anti-windup: the τ the allocator could deliver for the last update's τ."""
        back_calculate(self.gains, self.state, np.asarray(tau_achieved, dtype=float), float(dt))

    @property
    def reference(self) -> np.ndarray:
        """Current filtered reference (u, v, r) at the CoM."""
        return self.state[X_REF : X_REF + 3].copy()

    @property
    def reference_acceleration(self) -> np.ndarray:
        return self.state[A_REF : A_REF + 3].copy()

    @property
    def integrators(self) -> np.ndarray:
        """Integral terms (X [N], Y [N], N [N m])."""
        return self.state[INTEG : INTEG + 3].copy()

    @property
    def active(self) -> np.ndarray:
        """Which axes (surge, sway, yaw) are controlled; sway only on fully actuated vessels."""
        return self.gains[:, ACTIVE] > 0

    @property
    def max_velocity(self) -> np.ndarray:
        return self.gains[:, V_MAX].copy()

    def tuning(self, axis: str) -> AxisTuning:
        """The effective tuning of one axis ("surge", "sway", "yaw"); ki None = scheduled."""
        g = self.gains[AXES.index(axis)]
        return AxisTuning(g[LAMBDA], g[KP], None if g[KI] < 0 else g[KI], g[W_REF], g[A_MAX], g[V_MAX])


__all__ = ["AXES", "AxisTuning", "VelocityController", "actuator_time_constant", "design_gains"]
