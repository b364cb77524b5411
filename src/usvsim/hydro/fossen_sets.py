"""Parameter sets for the Fossen model: the Otter (PVS `otter.py`, physics.md §3.1) and the WAM-V
(VRX SimpleHydrodynamics main and classic, peer-simulators.md §2.3). All in Fossen's NED/FRD.

`otter_pvs()` also carries what the standalone reproduction of PVS needs (rigid body, payload,
restoring matrix G, propellers); `FossenParameters` is what the simulator uses.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from usvsim.hydro.fossen import FossenParameters, hoerner_cd, skew

G_MPS2 = 9.81


def h_matrix(r) -> np.ndarray:
    """H(r) = [[I, S(r)^T], [0, I]]: moves a 6-DOF quantity from point r to the origin."""
    H = np.eye(6)
    H[:3, 3:] = skew(r).T
    return H


@dataclass(frozen=True)
class OtterPVS:
    """Fossen's Otter as coded in PVS (FRD/NED, SI). Matrices 6×6 about CO (waterline, midships)."""

    m_total: float
    r_g: np.ndarray  # combined CG (hull + payload), m
    Ig: np.ndarray  # inertia about the CG (hull mass only + parallel-axis terms, as in PVS), kg m²
    M_RB: np.ndarray
    M_A: np.ndarray
    D: np.ndarray  # linear damping (positive)
    Dq: np.ndarray  # quadratic damping diagonal (the extra yaw term 10·D66)
    G: np.ndarray  # restoring matrix about CO (includes the payload in its equilibrium)
    cross_flow: tuple[float, float, float, float]  # L, T, C_D(Hoerner), rho = 1026
    m_payload: float
    r_payload: np.ndarray
    k_pos: float
    k_neg: float
    n_max: float
    n_min: float
    lever_y: tuple[float, float]  # l1, l2 (FRD y of the left and right propellers)
    T_n: float
    draft: float  # T, m
    waterplane_area: float  # both pontoons, m²
    gm_t: float  # transverse and longitudinal metacentric heights, m
    gm_l: float

    def hydro(self) -> FossenParameters:
        """The hydrodynamic part (FRD) as used in the simulator: M_A, D, D_Q, cross-flow, at CO."""
        return FossenParameters(self.M_A, self.D, self.Dq, self.cross_flow, None, True, "FRD")


def otter_pvs(rho: float = 1025.0, g: float = G_MPS2) -> OtterPVS:
    """Build the Otter exactly as PVS does (physics.md §3.1)."""
    L, B, m, m_p = 2.0, 1.08, 55.0, 25.0
    r_p, r_hull = np.array([0.05, 0.0, -0.35]), np.array([0.2, 0.0, -0.2])
    m_tot = m + m_p
    r_g = (m * r_hull + m_p * r_p) / m_tot
    R44, R55, R66 = 0.4 * B, 0.25 * L, 0.25 * L
    Ig = m * np.diag([R44**2, R55**2, R66**2]) - m * skew(r_g) @ skew(r_g) - m_p * skew(r_p) @ skew(r_p)
    MRB_CG = np.zeros((6, 6))
    MRB_CG[:3, :3], MRB_CG[3:, 3:] = m_tot * np.eye(3), Ig
    H = h_matrix(r_g)
    M_RB = H.T @ MRB_CG @ H
    M_A = np.diag([0.1 * m, 1.5 * m, 1.0 * m, 0.2 * Ig[0, 0], 0.8 * Ig[1, 1], 1.7 * Ig[2, 2]])
    M = M_RB + M_A
    B_pont, y_pont, Cw, Cb = 0.25, 0.395, 0.75, 0.4
    nabla = m_tot / rho
    T = nabla / (2 * Cb * B_pont * L)
    Aw = Cw * L * B_pont
    I_T = 2 * (1 / 12) * L * B_pont**3 * (6 * Cw**3 / ((1 + Cw) * (1 + 2 * Cw))) + 2 * Aw * y_pont**2
    I_L = 0.8 * 2 * (1 / 12) * B_pont * L**3
    KB = (1 / 3) * (5 * T / 2 - 0.5 * nabla / (L * B_pont))
    KG = T - r_g[2]
    GM_T, GM_L = KB + I_T / nabla - KG, KB + I_L / nabla - KG
    G_CF = np.diag([0.0, 0.0, rho * g * 2 * Aw, rho * g * nabla * GM_T, rho * g * nabla * GM_L, 0.0])
    H_cf = h_matrix([-0.2, 0.0, 0.0])
    G = H_cf.T @ G_CF @ H_cf
    w3, w4, w5 = (np.sqrt(G_CF[i, i] / M[i, i]) for i in (2, 3, 4))
    U_max = 6 * 0.5144
    D = np.diag([24.4 * g / U_max, M[1, 1] / 1.0, 2 * 0.3 * w3 * M[2, 2], 2 * 0.2 * w4 * M[3, 3],
                 2 * 0.4 * w5 * M[4, 4], M[5, 5] / 1.0])  # fmt: skip
    Dq = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 10.0 * D[5, 5]])
    k_pos, k_neg = 0.02216 / 2, 0.01289 / 2
    return OtterPVS(
        m_tot, r_g, Ig, M_RB, M_A, D, Dq, G, (L, T, hoerner_cd(B_pont, T), 1026.0), m_p, r_p, k_pos, k_neg,
        np.sqrt(0.5 * 24.4 * g / k_pos), -np.sqrt(0.5 * 13.6 * g / k_neg), (-0.395, 0.395), 0.1, T, 2 * Aw, GM_T,
        GM_L,
    )  # fmt: skip


# Fossen's CO in usvsim's Otter base_link (FLU, keel origin, m): on the design waterline (z = 0.195) and
# 0.153125 m aft of the centre of mass (vessels/otter.py COM x = -0.20612508), so that the CoM sits at Fossen's
# r_g = (0.153125, 0, -0.246875) (FRD) from it. The mesh hull's buoyancy centre (where its real CoM must be to
# float level) lies 0.2 m aft of midships, not 0.153 m forward as Fossen's; placing CO at midships instead
# put the lateral damping 0.2 m ahead of the CoM and made the full simulation directionally unstable at
# half power (a yaw kick grew into a 0.045 rad/s turn at n = 60 rad/s; PVS's equations damp it).
OTTER_CO_BASE_LINK = (-0.20612508 - 0.153125, 0.0, 0.195)


def otter(reference_point_base_link=OTTER_CO_BASE_LINK) -> FossenParameters:
    """Otter hydrodynamics for the simulator (FRD; convert with to_flu). Reference point: Fossen's CO,
    OTTER_CO_BASE_LINK (Fossen's r_g from the CoM; see there)."""
    p = otter_pvs().hydro()
    return FossenParameters(p.added_mass, p.linear_damping, p.quadratic_damping, p.cross_flow,
                            np.asarray(reference_point_base_link, dtype=float), True, "FRD")  # fmt: skip


VRX_MAIN = ((100.0, 100.0, 500.0, 300.0, 900.0, 800.0), (150.0, 100.0, 0.0, 600.0, 900.0, 800.0))
VRX_CLASSIC = ((51.3, 40.0, 500.0, 50.0, 50.0, 400.0), (72.4, 0.0, 0.0, 0.0, 0.0, 0.0))


def wamv_vrx(classic: bool = False) -> FossenParameters:
    """VRX's WAM-V SimpleHydrodynamics: added mass 0, diagonal linear + quadratic damping, no C_A,
    no cross-flow, wrench at the CoM (VRX-compatible; the values are sign-symmetric in FRD/FLU)."""
    lin, quad = VRX_CLASSIC if classic else VRX_MAIN
    return FossenParameters(np.zeros((6, 6)), np.diag(lin), np.array(quad), (0.0, 0.0, 0.0, 1025.0), None, False)


def from_config(cfg) -> FossenParameters:
    """FossenParameters from a `config.hydro_models.FossenHydrodynamics` section."""
    if cfg.parameters == "otter":
        p = otter() if cfg.reference_point is None else otter(cfg.reference_point)
    elif cfg.parameters in ("wamv_vrx", "wamv_vrx_classic"):
        p = wamv_vrx(cfg.parameters == "wamv_vrx_classic")
    else:
        L, T, B = cfg.cross_flow_length_m, cfg.cross_flow_draft_m, cfg.cross_flow_beam_m
        cd = hoerner_cd(B, T) if L > 0 and T > 0 and B > 0 else 0.0
        ref = None if cfg.reference_point is None else np.asarray(cfg.reference_point, dtype=float)
        p = FossenParameters(np.diag(cfg.added_mass), np.diag(cfg.linear_damping), np.asarray(cfg.quadratic_damping),
                             (L if cd else 0.0, T, cd, 1025.0), ref, cfg.added_mass_coriolis, "FRD")  # fmt: skip
    if cfg.vrx_compatible:
        p = FossenParameters(p.added_mass * 0, p.linear_damping, p.quadratic_damping, p.cross_flow,
                             p.reference_point, False, p.frame)  # fmt: skip
    return p
