"""Fossen's 6-DOF manoeuvring model: added mass, Coriolis-centripetal, damping, cross-flow drag.

τ_hyd = -M_A ν̇_r - C_A(ν_r) ν_r - D_L ν_r - D_Q (|ν_r| ∘ ν_r) + τ_crossflow(ν_r)   (Fossen 2021)
ν_r = ν - ν_c: velocity relative to the water at the model's reference point (Fossen's CO).

Frames. Fossen gives coefficients in NED/FRD; usvsim works in ENU/FLU. FLU is FRD turned by π
about x, T = diag(1, -1, -1) for vectors and, being a proper rotation, for pseudo-vectors too, so
T6 = diag(1, -1, -1, 1, -1, -1) and every 6×6 matrix becomes T6 M T6 (`to_flu`, done once at load).
m2c and |ν|∘ν commute with T6; the cross-flow strip sum is odd in (v, r), so it is unchanged.
Restoring forces G are NOT part of the in-simulator model (the mesh hydrostatics provide them);
`fossen_sets.otter_pvs()` carries G for the standalone reproduction of PVS.

In the simulator the rigid-body terms (M_RB, C_RB) belong to MuJoCo; this module adds only the
hydrodynamic wrench. Added mass is applied as a force -M_A ν̇ with ν̇ taken from the previous step
(as VRX does); see `FossenForces` and `split_added_mass` for stability and an implicit option.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numba import njit

from usvsim.core.transforms import cross3

T6 = np.diag([1.0, -1.0, -1.0, 1.0, -1.0, -1.0])
# Hoerner's 2-D cross-flow drag coefficient vs B/(2T) (digitized curve, as used by Fossen's MSS)
HOERNER_B2T = np.array([0.0109, 0.1766, 0.3530, 0.4519, 0.4728, 0.4929, 0.4933, 0.5585, 0.6464, 0.8336,
                        0.9880, 1.3081, 1.6392, 1.8600, 2.3129, 2.6000, 3.0088, 3.4508, 3.7379, 4.0031])
HOERNER_CD = np.array([1.9661, 1.9657, 1.8976, 1.7872, 1.5837, 1.2786, 1.2108, 1.0836, 0.9986, 0.8796,
                       0.8284, 0.7599, 0.6914, 0.6571, 0.6307, 0.5962, 0.5868, 0.5859, 0.5599, 0.5593])


def hoerner_cd(beam_m: float, draft_m: float) -> float:
    """2-D cross-flow drag coefficient of a section of beam B and draft T (Hoerner's curve)."""
    return float(np.interp(beam_m / (2.0 * draft_m), HOERNER_B2T, HOERNER_CD))


def skew(a) -> np.ndarray:
    """S(a) with S(a) b = a × b."""
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def m2c(M: np.ndarray, nu: np.ndarray) -> np.ndarray:
    """Coriolis-centripetal matrix of a 6×6 mass matrix (symmetrised first), Fossen's m2c."""
    M = 0.5 * (M + M.T)
    a = M[:3, :3] @ nu[:3] + M[:3, 3:] @ nu[3:]
    b = M[3:, :3] @ nu[:3] + M[3:, 3:] @ nu[3:]
    C = np.zeros((6, 6))
    C[:3, 3:], C[3:, :3], C[3:, 3:] = -skew(a), -skew(a), -skew(b)
    return C


@dataclass(frozen=True)
class FossenParameters:
    """One vessel's hydrodynamic coefficients in one frame (`frame` "FRD" or "FLU").

    added_mass (6,6) kg, kg·m, kg·m² (M_A, positive definite); linear_damping (6,6) (D_L, positive);
    quadratic_damping (6,) (diagonal D_Q, positive); cross_flow = (L m, T m, C_D, rho kg/m³), L = 0
    disables; reference_point (3,) m: Fossen's CO in the vessel's base_link (FLU, never converted),
    None = the centre of mass; coriolis_added_mass: include C_A(ν_r) ν_r (False: VRX-compatible).
    """

    added_mass: np.ndarray
    linear_damping: np.ndarray
    quadratic_damping: np.ndarray
    cross_flow: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 1025.0)
    reference_point: np.ndarray | None = None
    coriolis_added_mass: bool = True
    frame: str = "FRD"

    def to_flu(self) -> FossenParameters:
        """The same model in FLU (T6 M T6). Identity when already FLU."""
        if self.frame == "FLU":
            return self
        return replace(self, added_mass=T6 @ self.added_mass @ T6, linear_damping=T6 @ self.linear_damping @ T6,
                       frame="FLU")  # fmt: skip


@njit(cache=True)
def cross_flow(v, r, length, draft, cd, rho):
    """Strip-theory cross-flow drag (Y, N) from sway v and yaw rate r: 21 strips x = -L/2..L/2,
    dx = L/20 (Fossen's crossFlowDrag, total weight 1.05 L)."""
    dx = length / 20.0
    y = n = 0.0
    for i in range(21):
        x = -0.5 * length + i * dx
        u = v + x * r
        q = -0.5 * rho * draft * cd * abs(u) * u * dx
        y += q
        n += x * q
    return y, n


@njit(cache=True)
def hydro_wrench(Ma, Dl, Dq, cf, use_ca, nu, nu_dot, out):
    """out (6,) = -M_A ν̇ - C_A(ν)ν - D_L ν - D_Q |ν|∘ν + τ_cf(ν), all at the reference point, one frame.

    Ma, Dl (6,6); Dq (6,); cf (4,) = (L, T, C_D, rho); nu, nu_dot (6,) relative to the water.
    """
    for i in range(6):
        acc = -Dq[i] * abs(nu[i]) * nu[i]
        for j in range(6):
            acc -= Ma[i, j] * nu_dot[j] + Dl[i, j] * nu[j]
        out[i] = acc
    if use_ca:  # C_A ν = [ν2 × a ; ν1 × a + ν2 × b], a = M11 ν1 + M12 ν2, b = M21 ν1 + M22 ν2
        a0 = a1 = a2 = b0 = b1 = b2 = 0.0
        for j in range(6):
            a0 += 0.5 * (Ma[0, j] + Ma[j, 0]) * nu[j]
            a1 += 0.5 * (Ma[1, j] + Ma[j, 1]) * nu[j]
            a2 += 0.5 * (Ma[2, j] + Ma[j, 2]) * nu[j]
            b0 += 0.5 * (Ma[3, j] + Ma[j, 3]) * nu[j]
            b1 += 0.5 * (Ma[4, j] + Ma[j, 4]) * nu[j]
            b2 += 0.5 * (Ma[5, j] + Ma[j, 5]) * nu[j]
        u, v, w, p, q, r = nu[0], nu[1], nu[2], nu[3], nu[4], nu[5]
        out[0] -= q * a2 - r * a1
        out[1] -= r * a0 - p * a2
        out[2] -= p * a1 - q * a0
        out[3] -= v * a2 - w * a1 + q * b2 - r * b1
        out[4] -= w * a0 - u * a2 + r * b0 - p * b2
        out[5] -= u * a1 - v * a0 + p * b1 - q * b0
    if cf[0] > 0.0:
        y, n = cross_flow(nu[1], nu[5], cf[0], cf[1], cf[2], cf[3])
        out[1] += y
        out[5] += n


@njit(cache=True)
def fossen_wrenches(Ma, Dl, Dq, cf, use_ca, ref, nu_com, nu_dot_ref, nu_ref, tmp, out):
    """Batched hydro_wrench for nb bodies, converted between the CoM and each reference point.

    nu_com (nb,6): body-frame (FLU) velocity relative to the water at the CoM; ref (nb,3): reference
    point minus CoM (body frame, m); nu_dot_ref (nb,6) acceleration at the reference point.
    Outputs: nu_ref (nb,6) velocity at the reference point; out (nb,6) wrench about the CoM, body
    frame (N, N·m); tmp (6,) scratch.
    """
    for b in range(nu_com.shape[0]):
        rx, ry, rz = ref[b, 0], ref[b, 1], ref[b, 2]
        p, q, r = nu_com[b, 3], nu_com[b, 4], nu_com[b, 5]
        nu_ref[b, 0] = nu_com[b, 0] + q * rz - r * ry
        nu_ref[b, 1] = nu_com[b, 1] + r * rx - p * rz
        nu_ref[b, 2] = nu_com[b, 2] + p * ry - q * rx
        nu_ref[b, 3], nu_ref[b, 4], nu_ref[b, 5] = p, q, r
        hydro_wrench(Ma[b], Dl[b], Dq[b], cf[b], use_ca[b], nu_ref[b], nu_dot_ref[b], tmp)
        fx, fy, fz = tmp[0], tmp[1], tmp[2]
        out[b, 0], out[b, 1], out[b, 2] = fx, fy, fz
        out[b, 3] = tmp[3] + ry * fz - rz * fy
        out[b, 4] = tmp[4] + rz * fx - rx * fz
        out[b, 5] = tmp[5] + rx * fy - ry * fx


def added_mass_at(added_mass: np.ndarray, r) -> np.ndarray:
    """M_A (6,6) given at a reference point, expressed at a point from which the reference point lies at r (3,)
    (same axes): H(r)^T M_A H(r), ν_ref = H(r) ν (kinetic energy preserved; Kirchhoff's equations keep their form)."""
    h = np.eye(6)
    h[:3, 3:] = skew(r).T
    return h.T @ np.asarray(added_mass, dtype=float) @ h


@njit(cache=True)
def added_mass_wrenches(Ma, Mc, use_ca, nu_com, nu_dot_com, tmp, out):
    """out[b] += -Ma[b] ν̇ - C_A(Mc[b]) ν at the CoM (body FLU): the added mass that MuJoCo's armature leaves
    out (Ma: the rest of M_A at the CoM; Mc: M_A at the CoM minus the translational armature, whose Coriolis
    terms MuJoCo's world-frame translations already carry)."""
    zero_d, zero_q, no_cf = np.zeros((6, 6)), np.zeros(6), np.zeros(4)
    for b in range(nu_com.shape[0]):
        hydro_wrench(Ma[b], zero_d, zero_q, no_cf, False, nu_com[b], nu_dot_com[b], tmp)
        for i in range(6):
            out[b, i] += tmp[i]
        if use_ca[b]:
            hydro_wrench(Mc[b], zero_d, zero_q, no_cf, True, nu_com[b], zero_q, tmp)
            for i in range(6):
                out[b, i] += tmp[i]


def split_added_mass(added_mass_diag, mass_kg: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Split a diagonal M_A (FLU, 6) into MuJoCo free-joint armature (implicit) and an explicit rest.

    Free-joint dofs: 3 translations in WORLD axes, 3 rotations in BODY axes. Armature on the
    rotations is exactly diag(K_ṗ, M_q̇, N_ṙ) (about the joint origin); on the translations it must
    be isotropic in the horizontal plane, so surge/sway get a_h = (X_u̇ + Y_v̇)/2 and heave Z_ẇ
    (exact for small roll/pitch). The rest ΔM = M_A - diag(a) is applied as -ΔM ν̇_prev; the lagged
    force is stable when max|ΔM_ii| / (m + a_ii) < 1 (returned as `ratio`; the pure explicit form has
    ratio M_A,ii / m, e.g. 1.03 for the Otter's sway: unstable).
    Returns (armature (6,), explicit diagonal (6,), ratio).
    """
    ma = np.asarray(added_mass_diag, dtype=float)
    a_h = 0.5 * (ma[0] + ma[1])
    armature = np.array([a_h, a_h, ma[2], ma[3], ma[4], ma[5]])
    rest = ma - armature
    ratio = float(max(abs(rest[0]), abs(rest[1])) / (mass_kg + a_h))
    return armature, rest, ratio


class FossenForces:
    """Fossen hydrodynamic wrenches of nb bodies (body frame FLU, about each CoM).

    params: FossenParameters per body (converted to FLU here); com_body (nb,3) CoM in base_link.
    explicit_added_mass (nb,6,6) optional: the part of M_A applied as a lagged force (default all of
    it; pass the rest from `split_added_mass` when the diagonal goes into MuJoCo's armature).
    filter_s: first-order low-pass time constant on the finite-difference ν̇ (0 = none).
    State: ν_r at each reference point on the previous step and the filtered ν̇ (`reset()` clears).
    """

    def __init__(self, params, com_body, explicit_added_mass=None, filter_s: float = 0.0, at_com=None):
        """at_com: optional (Ma (nb,6,6), Mc (nb,6,6)): the added mass is then applied at the CoM (see
        `added_mass_wrenches`) and only damping and cross-flow at the reference point."""
        flu = [p.to_flu() for p in params]
        nb = len(flu)
        com = np.asarray(com_body, dtype=float).reshape(nb, 3)
        self.Ma = np.array([p.added_mass for p in flu]).reshape(nb, 6, 6)
        if explicit_added_mass is not None:
            self.Ma = np.asarray(explicit_added_mass, dtype=float).reshape(nb, 6, 6).copy()
        self.Dl = np.array([p.linear_damping for p in flu]).reshape(nb, 6, 6)
        self.Dq = np.array([p.quadratic_damping for p in flu]).reshape(nb, 6)
        self.cf = np.array([p.cross_flow for p in flu], dtype=float).reshape(nb, 4)
        self.use_ca = np.array([p.coriolis_added_mass for p in flu], dtype=np.bool_)
        self.ref = np.array([com[i] * 0 if p.reference_point is None else np.asarray(p.reference_point) - com[i]
                             for i, p in enumerate(flu)]).reshape(nb, 3)  # fmt: skip
        self.filter_s = float(filter_s)
        self.at_com: tuple[np.ndarray, np.ndarray] | None = None
        if at_com is not None:
            ma, mc = (np.ascontiguousarray(np.asarray(m, dtype=float).reshape(nb, 6, 6)) for m in at_com)
            self.at_com = (ma, mc)
            self.Ma = np.zeros((nb, 6, 6))
        self._nu_ref, self._nu_prev = np.zeros((nb, 6)), np.zeros((nb, 6))
        self._nu_dot, self._tmp, self._out = np.zeros((nb, 6)), np.zeros(6), np.zeros((nb, 6))
        self._ready = False

    def reset(self) -> None:
        self._ready = False
        self._nu_dot[:] = 0.0

    def compute(self, nu_com: np.ndarray, dt: float) -> np.ndarray:
        """Wrench (nb,6) body frame FLU about the CoM from ν relative to the water at the CoM (nb,6)."""
        nu_ref = self._nu_ref
        nu_ref[:, :3] = nu_com[:, :3] + cross3(nu_com[:, 3:], self.ref)
        nu_ref[:, 3:] = nu_com[:, 3:]
        tracked = nu_ref if self.at_com is None else nu_com  # where ν̇ is needed
        if self._ready:
            raw = (tracked - self._nu_prev) / dt
            alpha = dt / (self.filter_s + dt)
            self._nu_dot += alpha * (raw - self._nu_dot)
        self._nu_prev[:] = tracked
        self._ready = True
        nu_com = np.ascontiguousarray(nu_com)
        use_ca = self.use_ca if self.at_com is None else np.zeros_like(self.use_ca)
        fossen_wrenches(self.Ma, self.Dl, self.Dq, self.cf, use_ca, self.ref, nu_com, self._nu_dot, nu_ref,
                        self._tmp, self._out)  # fmt: skip
        if self.at_com is not None:
            added_mass_wrenches(*self.at_com, self.use_ca, nu_com, self._nu_dot, self._tmp, self._out)
        return self._out
