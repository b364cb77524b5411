"""The 3-DOF horizontal-plane model a controller is designed on, taken from the vessel's own parameters.

    M ν̇ + C(ν) ν + D(ν) ν = τ,   ν = (u [m/s], v [m/s], r [rad/s]) at the CoM, body FLU,
    M = diag(m + A_u, m + A_v, I_zz + A_r),  C(ν) ν = (-m v r, m u r, 0),  D(ν) ν in the form of a
    `StateSpaceDrag` (usvsim.hydro.statespace: X_u u + X_uu |u|u + X_uuu u³, Y_v v + ... + Y_r r, N_r r + ... + N_v v).

D and the added mass A come from the vessel's hydrodynamics (`from_body_model`): a state-space drag as it is
(no added mass: MuJoCo carries the rigid body only); Fossen's model as its damping (linear, quadratic and the
cross-flow's quadratic sway and yaw) and the diagonal of its added mass, taken at the CoM (its reference point may
sit elsewhere: a design model); Kerner's per-face forces, which have no coefficients, as the estimate an
unidentified hull gets (`vessels.custom.estimated_drag`). Linearized per axis about ν₀: m ẋ + d x = τ with
d = ∂(Dν)/∂x at ν₀.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from usvsim.config.hydro_models import FossenHydrodynamics, KernerHydrodynamics
from usvsim.config.vessel import StateSpaceDrag
from usvsim.hydro.statespace import FIELDS, coefficients


@njit(cache=True)
def damping_force(c, u, v, r, out):
    """out = D(ν)ν for the planar DOFs (X [N], Y [N], N [N m]); `c` in `statespace.FIELDS` order."""
    out[0] = c[0] * u + c[1] * abs(u) * u + c[2] * u * u * u
    out[1] = c[3] * v + c[4] * abs(v) * v + c[5] * v * v * v + c[6] * r
    out[2] = c[13] * r + c[14] * abs(r) * r + c[15] * r * r * r + c[16] * v


@njit(cache=True)
def damping_slope(c, u, v, r, out):
    """out = diagonal of ∂(D(ν)ν)/∂ν: the linearized damping per axis (N s/m, N m s)."""
    out[0] = c[0] + 2.0 * c[1] * abs(u) + 3.0 * c[2] * u * u
    out[1] = c[3] + 2.0 * c[4] * abs(v) + 3.0 * c[5] * v * v
    out[2] = c[13] + 2.0 * c[14] * abs(r) + 3.0 * c[15] * r * r


@dataclass(frozen=True)
class PlantModel:
    """Mass [kg], yaw inertia about the CoM [kg m²], drag coefficients (FIELDS order), CoM in base_link, added
    mass in surge, sway [kg] and yaw [kg m²]."""

    mass_kg: float
    inertia_z_kgm2: float
    drag: np.ndarray
    com_flu_m: np.ndarray
    added_mass: np.ndarray = field(default_factory=lambda: np.zeros(3))

    @classmethod
    def from_body_model(cls, model) -> PlantModel:
        """From a `usvsim.vessels.model.BodyModel` (or a vessel handle's `.model`), whatever its hydrodynamics
        (see the module text)."""
        mass, izz = float(model.mass_kg), float(np.asarray(model.inertia)[2, 2])
        added = np.zeros(3)
        hydro = model.drag
        if isinstance(hydro, FossenHydrodynamics):
            hydro, added = _fossen_design(hydro)
        elif isinstance(hydro, KernerHydrodynamics):
            from usvsim.vessels.custom import estimated_drag

            hydro = estimated_drag(model.hull, mass, np.asarray(model.inertia))
        assert isinstance(hydro, StateSpaceDrag), f"no plant model for {type(hydro).__name__}"
        return cls(mass, izz, coefficients([hydro])[0], np.asarray(model.com, float), added)

    @property
    def inertia_diag(self) -> np.ndarray:
        return np.array([self.mass_kg, self.mass_kg, self.inertia_z_kgm2]) + self.added_mass

    def damping(self, nu) -> np.ndarray:
        out = np.empty(3)
        damping_force(self.drag, float(nu[0]), float(nu[1]), float(nu[2]), out)
        return out

    def slope(self, nu) -> np.ndarray:
        out = np.empty(3)
        damping_slope(self.drag, float(nu[0]), float(nu[1]), float(nu[2]), out)
        return out

    def max_speed(self, axis: int, force: float) -> float:
        """Steady speed on `axis` (0 surge, 1 sway, 2 yaw) at which the damping balances `force` (bisection);
        inf when the axis has no damping."""
        if force <= 0:
            return 0.0
        nu = np.zeros(3)
        hi = 1.0
        while True:
            nu[axis] = hi
            if self.damping(nu)[axis] >= force:
                break
            hi *= 2.0
            if hi > 1e6:
                return math.inf
        lo = 0.0
        for _ in range(60):
            nu[axis] = mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if self.damping(nu)[axis] < force else (lo, mid)
        return 0.5 * (lo + hi)


def _fossen_design(cfg: FossenHydrodynamics) -> tuple[StateSpaceDrag, np.ndarray]:
    """Fossen's model as planar state-space drag and (surge, sway, yaw) added mass, FLU (see the module text)."""
    from usvsim.hydro.fossen_sets import from_config

    p = from_config(cfg).to_flu()
    d, q, ma = p.linear_damping, p.quadratic_damping, p.added_mass
    y_vv, n_rr = float(q[1]), float(q[5])
    length, draft, cd, rho = p.cross_flow
    if length > 0:  # the strip sum of `fossen.cross_flow` at pure sway and pure yaw: 21 strips, dx = L/20
        x = np.linspace(-length / 2, length / 2, 21)
        y_vv += 0.5 * rho * draft * cd * length / 20 * len(x)
        n_rr += 0.5 * rho * draft * cd * length / 20 * float(np.sum(x**2 * np.abs(x)))
    drag = StateSpaceDrag(X_u=float(d[0, 0]), X_uu=float(q[0]), Y_v=float(d[1, 1]), Y_vv=y_vv, Y_r=float(d[1, 5]),
                          N_r=float(d[5, 5]), N_rr=n_rr, N_v=float(d[5, 1]))  # fmt: skip
    return drag, np.array([ma[0, 0], ma[1, 1], ma[5, 5]])


def com_velocity(nu_origin_flu: np.ndarray, omega_flu: np.ndarray, com_flu_m: np.ndarray) -> np.ndarray:
    """Planar (u, v, r) at the CoM from the base_link origin's velocity and the angular velocity (body FLU)."""
    (u, v, _), (p, q, r), (x, y, z) = nu_origin_flu, omega_flu, com_flu_m
    return np.array([u + q * z - r * y, v + r * x - p * z, r], dtype=float)


def reference_at_com(nu_ref_base: np.ndarray, com_flu_m: np.ndarray) -> np.ndarray:
    """A planar velocity reference for base_link (u, v, r) expressed at the CoM: u - r y_c, v + r x_c."""
    u, v, r = (float(x) for x in nu_ref_base)
    return np.array([u - r * com_flu_m[1], v + r * com_flu_m[0], r])


__all__ = ["FIELDS", "PlantModel", "com_velocity", "damping_force", "damping_slope", "reference_at_com"]
