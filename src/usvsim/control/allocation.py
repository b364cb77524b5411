"""Thrust allocation: a generalized force τ = (X [N], Y [N], N [N m]) about the CoM (body FLU) → per-thruster
commands (normalized thrust u in [-1, 1] through the exact inverse of each thruster's map, azimuth angle rad).

`PseudoInverseAllocator` — the seed's method (physics.md §5.2): weighted least-norm extended-thrust vector
f = W⁻¹Bᵀ(BW⁻¹Bᵀ)⁻¹τ, azimuths converted to angle and magnitude (reverse thrust at angle + π when the
forward angle is outside the azimuth range). B f = τ exactly; limits are not respected (u is clipped).

`ConstrainedAllocator` — respects thrust, thrust-rate, angle and angle-rate limits:
1. azimuth directions from the weighted pseudo-inverse, kept inside the azimuth range (forward or
   reverse, whichever is closer to the current angle), held when the desired force vanishes;
2. each azimuth's effective angle over the control period: its servo's first-order lag and rate limit
   from the current angle (so the thrust is computed where the thruster will actually point);
3. thrusts by box-constrained least squares at those angles (exact primal active-set QP):
   min (Bt - τ)ᵀ Q (Bt - τ) + tᵀ W t,  -T_rev ≤ t ≤ T_fwd (∩ thrust rate bound).
Q ≫ W (default ratio 1e6 in normalized units), so τ is met whenever it is attainable at those angles
and the least-squares compromise is returned otherwise; `tau_achieved` is what the commands produce and
feeds the velocity controller's anti-windup. Yaw gets `yaw_priority` times the weight of the forces.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from usvsim.control.allocation_kernels import (
    ANGLE_CMD,
    ANGLE_EFF,
    THRUST,
    U,
    allocate_constrained,
    allocate_unconstrained,
)
from usvsim.control.layout import ThrusterLayout, extended_weights, weighted_pseudo_inverse


@dataclass(frozen=True)
class Allocation:
    """Per-thruster results in layout order, and the τ (X, Y, N) they achieve."""

    names: tuple[str, ...]
    thrust_n: np.ndarray  # signed thrust the allocator asks for (N)
    angle_rad: np.ndarray  # azimuth angle command (rad, CCW from the mount heading; 0 for fixed)
    angle_effective_rad: np.ndarray  # angle the thrust is computed at (constrained: after the servo's dt)
    u: np.ndarray  # normalized thrust command in [-1, 1]
    tau_achieved: np.ndarray

    def commands(self) -> dict[str, tuple[float, float]]:
        """{thruster name: (u, angle_rad)}, ready for `vessel.thrusters[name].command(u, angle_rad)`."""
        return {n: (float(self.u[i]), float(self.angle_rad[i])) for i, n in enumerate(self.names)}


class _Allocator:
    def __init__(self, layout: ThrusterLayout, column_weights=None):
        self.layout = layout
        w = extended_weights(layout.params) if column_weights is None else np.asarray(column_weights, float)
        self.pinv = np.ascontiguousarray(weighted_pseudo_inverse(layout.extended, w))
        self._angle = np.zeros(layout.n)
        self._thrust = np.zeros(layout.n)

    def reset(self) -> None:
        """Forget the remembered angles and thrusts (used when the current ones are not given)."""
        self._angle[:] = 0.0
        self._thrust[:] = 0.0

    def _result(self, out: np.ndarray, tau_out: np.ndarray) -> Allocation:
        self._angle = out[:, ANGLE_EFF].copy()
        self._thrust = out[:, THRUST].copy()
        return Allocation(
            self.layout.names, out[:, THRUST], out[:, ANGLE_CMD], out[:, ANGLE_EFF], out[:, U], tau_out
        )

    def _now(self, angle_now_rad, thrust_now_n):
        a = self._angle if angle_now_rad is None else np.asarray(angle_now_rad, dtype=float)
        t = self._thrust if thrust_now_n is None else np.asarray(thrust_now_n, dtype=float)
        return a, t


class PseudoInverseAllocator(_Allocator):
    """Unconstrained weighted pseudo-inverse allocation. `column_weights`: one weight per extended
    column (azimuth thrusters have two); default 1/T_max² of each thruster."""

    def allocate(self, tau, angle_now_rad=None, thrust_now_n=None, dt: float = 0.0) -> Allocation:
        """τ (X [N], Y [N], N [N m]) about the CoM → commands. `angle_now_rad` is only used to hold the
        angle of an azimuth whose desired force is zero (default: the last command)."""
        angle, _ = self._now(angle_now_rad, thrust_now_n)
        out, tau_out = np.empty((self.layout.n, 4)), np.empty(3)
        allocate_unconstrained(np.asarray(tau, dtype=float), self.layout.params, self.pinv, self.layout.columns,
                               angle, out, tau_out)  # fmt: skip
        return self._result(out, tau_out)


class ConstrainedAllocator(_Allocator):
    """Limit-respecting allocation (see the module docstring). `tau_weights`: Q on (X, Y, N) residuals
    (default: normalized by the layout's capacity, yaw × `yaw_priority`, × 1e6 over the thrust weights);
    the thrust weights are the layout's per-thruster weights over T_max²."""

    def __init__(self, layout: ThrusterLayout, tau_weights=None, yaw_priority: float = 10.0,
                 reverse_bias_rad: float = math.pi / 4, column_weights=None):  # fmt: skip
        super().__init__(layout, column_weights)
        if tau_weights is None:
            cap = layout.capacity()
            cap = np.where(cap > 1e-9 * max(cap.max(), 1.0), cap, max(cap.max(), 1.0))
            tau_weights = 1e6 * np.array([1.0, 1.0, yaw_priority]) / cap**2
        self.tau_weights = np.asarray(tau_weights, dtype=float)
        self.reverse_bias_rad = float(reverse_bias_rad)

    def allocate(self, tau, angle_now_rad=None, thrust_now_n=None, dt: float = 0.05) -> Allocation:
        """τ → commands that respect every limit over the next control period `dt` (s), starting from the
        thrusters' current angles and thrusts (default: what this allocator commanded last)."""
        angle, thrust = self._now(angle_now_rad, thrust_now_n)
        out, tau_out = np.empty((self.layout.n, 4)), np.empty(3)
        allocate_constrained(np.asarray(tau, dtype=float), self.layout.params, self.pinv, self.layout.columns,
                             self.tau_weights, angle, thrust, float(dt), self.reverse_bias_rad, out, tau_out)  # fmt: skip
        return self._result(out, tau_out)


ALLOCATORS = {"unconstrained": PseudoInverseAllocator, "constrained": ConstrainedAllocator}
