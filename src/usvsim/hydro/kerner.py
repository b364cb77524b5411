"""Kerner hydrodynamics for all hulls of a `HullSet`: coefficient table, slamming state, one call.

Usage per physics step (world ENU, SI):
    kerner = KernerForces(hulls, [KernerHydrodynamics(), ...], masses_kg, lengths_m)
    verts = hulls.world_vertices(pos, rot); eta = ocean.elevation(...); u_w = ocean.velocity(...)
    res = kerner.compute(verts, eta, u_w, com_world, vcom_world, omega_world, u_w_com, wind, dt)
    res.force, res.torque   # (nb,3) world, torque about each CoM; res.parts (nb,4,6) by kind

State kept: the previous step's submerged area per face (for slamming) and whether it is
valid (`reset()` after a teleport). Kinematic viscosity: 1.19e-6 m²/s by default (sea water at 15 °C,
consistent with the default sea-water density); asv_wave_sim's 1.0533e-6 (fresh water near 18 °C) gives a
C_F 2.4 % higher at Rn ~ 5e6. (The seed used 1.0016, 10^6 too large.)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit

from usvsim.config.hydro_models import KernerHydrodynamics
from usvsim.hydro import kerner_kernels as kk
from usvsim.hydro.hydrostatics import HullSet
from usvsim.hydro.kerner_air import anchor_frames, dry_face_table

PARTS = ("viscous", "pressure", "slamming", "air")


def coefficient_row(cfg: KernerHydrodynamics, mass_kg: float, length_m: float, hull_area_m2: float,
                    rho_water: float = 1025.0, rho_air: float = 1.225) -> np.ndarray:
    """One body's row of the kernel's coefficient table (columns named in kerner_kernels)."""
    row = np.zeros(kk.N_COEF)
    row[[kk.RHO, kk.NU, kk.FORM_K, kk.RN_MIN, kk.VISC_SCALE]] = (
        rho_water, cfg.kinematic_viscosity_m2ps, cfg.form_factor_k, cfg.reynolds_min, cfg.viscous_scale)
    row[[kk.CPD1, kk.CPD2, kk.FP, kk.CSD1, kk.CSD2, kk.FS, kk.VREF, kk.PRES_SCALE]] = (
        cfg.pressure_linear_pa, cfg.pressure_quadratic_pa, cfg.pressure_falloff, cfg.suction_linear_pa,
        cfg.suction_quadratic_pa, cfg.suction_falloff, cfg.reference_speed_mps, cfg.pressure_scale)
    row[[kk.SLAM_P, kk.SLAM_SPEED, kk.SLAM_SCALE]] = (cfg.slamming_power, cfg.slamming_speed_mps, cfg.slamming_scale)
    row[[kk.RHO_AIR, kk.C_AIR, kk.AIR_SCALE]] = (rho_air, cfg.air_drag_coefficient, cfg.air_scale)
    row[[kk.LENGTH, kk.MASS, kk.AREA]] = (length_m, mass_kg, hull_area_m2)
    return row


@dataclass(frozen=True, slots=True)
class KernerResult:
    """Views of the output buffers (world ENU, SI), overwritten by the next compute()."""

    force: np.ndarray  # (nb,3) N, sum of all kinds
    torque: np.ndarray  # (nb,3) N·m about each CoM
    parts: np.ndarray  # (nb,4,6) per kind (PARTS order): force, torque


@njit(cache=True)
def waterline_lengths(seg, count, face_offsets, rot, out):
    """out[b] = extent (m) along body b's x axis (rot[b][:, 0], world) of its waterline segments (seg (Nf,2,3)
    world m, rows with count 1, from the hydrostatics); bodies without a waterline keep their value."""
    for b in range(face_offsets.shape[0] - 1):
        ax, ay, az = rot[b, 0, 0], rot[b, 1, 0], rot[b, 2, 0]
        lo, hi = np.inf, -np.inf
        for f in range(face_offsets[b], face_offsets[b + 1]):
            if count[f]:
                for e in range(2):
                    x = seg[f, e, 0] * ax + seg[f, e, 1] * ay + seg[f, e, 2] * az
                    lo, hi = min(lo, x), max(hi, x)
        if hi > lo:
            out[b] = hi - lo


class KernerForces:
    """Kerner forces of every hull in `hulls`; one coefficient row per body.

    configs: one KernerHydrodynamics per body; masses_kg (nb,); lengths_m (nb,) reference length for
    the Reynolds number (default: each hull's extent along body x, until `set_waterline` gives the length
    of the actual waterline). One core: the bodies run in
    sequence (threading them through numba's prange cost far more than it saved on a shared machine).
    """

    def __init__(self, hulls: HullSet, configs: Sequence[KernerHydrodynamics], masses_kg: Sequence[float],
                 lengths_m: Sequence[float] | None = None, rho_water: float = 1025.0, rho_air: float = 1.225):
        nb = hulls.n_bodies
        if len(configs) != nb or len(masses_kg) != nb:
            raise ValueError("one Kerner configuration and one mass per hull body")
        fo = hulls.face_offsets.astype(np.int64)
        vo = hulls.vert_offsets
        if lengths_m is None:
            lengths_m = [np.ptp(hulls.vertices_body[vo[b]:vo[b + 1], 0]) for b in range(nb)]
        areas = [hulls.face_area[fo[b]:fo[b + 1]].sum() for b in range(nb)]
        self.hulls = hulls
        self.coef = np.ascontiguousarray(np.array(
            [coefficient_row(c, m, L, a, rho_water, rho_air)
             for c, m, L, a in zip(configs, masses_kg, lengths_m, areas)]).reshape(nb, kk.N_COEF))  # fmt: skip
        nf = len(hulls.faces)
        self._geom = kk.face_geometry(hulls.face_area)  # rigid-motion invariant per-face table
        self._vert_offsets = hulls.vert_offsets.astype(np.int64)
        # pressure/suction pieces (at most two per face, see kerner_terms) and their |cos θ|^f
        self._pieces, self._powed = np.zeros((kk.N_PIECE_ROWS, 2 * nf)), np.zeros(2 * nf)
        self._first = np.zeros(nb + 1, dtype=np.int64)
        # whole dry faces: air drag from body-frame tables (kerner_air)
        self._air = (np.zeros(nf), dry_face_table(hulls.vertices_body, hulls.faces),
                     *anchor_frames(hulls.vertices_body, hulls.vert_offsets))  # fmt: skip
        self._lengths = np.zeros(nb)
        self._first_lengths = self.coef[:, kk.LENGTH].copy()  # until the first step's waterline
        self._swept = np.zeros((nf, 3))
        self._swept_prev = np.zeros((nf, 3))
        self._ready = False
        self._parts = np.zeros((nb, 4, 6))
        self._force, self._torque = np.zeros((nb, 3)), np.zeros((nb, 3))
        self._result = KernerResult(self._force, self._torque, self._parts)

    def set_waterline(self, hydrostatics, rot: np.ndarray) -> None:
        """Reynolds length of each body := the length of its waterline along its x axis (from a
        HydrostaticsResult, world; rot (nb,3,3) body → world), for the next compute(). Bodies with no
        waterline (all dry or all submerged) keep theirs."""
        self._lengths[:] = self.coef[:, kk.LENGTH]
        waterline_lengths(hydrostatics.waterline_segments, hydrostatics.waterline_count, self.hulls.face_offsets,
                          rot, self._lengths)  # fmt: skip
        self.coef[:, kk.LENGTH] = self._lengths

    def reset(self) -> None:
        """Forget the previous step (no slamming on the next call; the Reynolds lengths of the first step), e.g.
        after moving a body or a simulation reset."""
        self._ready = False
        self.coef[:, kk.LENGTH] = self._first_lengths

    def set_previous_areas(self, area_prev: np.ndarray) -> None:
        """Set the previous step's submerged area of each face (Nf,) m² (tests, restarts)."""
        self._swept_prev[:, 0] = area_prev
        self._ready = True

    def compute(self, world_vertices, eta, water_vel, com_world, vcom_world, omega_world,
                water_vel_com, wind, dt: float) -> KernerResult:
        """Forces for this step; advances the slamming state. Arrays as in kerner_wrenches."""
        h, pieces = self.hulls, self._pieces
        q = kk.kerner_wrenches(world_vertices, h.faces, self._geom, h.face_offsets, self._vert_offsets, eta,
                               water_vel, com_world, vcom_world, omega_world, water_vel_com, wind, self.coef, float(dt),
                               self._ready, self._swept_prev, self._swept, self._parts, pieces,
                               self._first, self._air)  # fmt: skip
        # |cos θ|^f of all pressure pieces, one SIMD np.power (about 4x cheaper than pow per piece)
        np.power(pieces[kk.P_COS, :q], pieces[kk.P_EXP, :q], out=self._powed[:q])
        kk.pressure_wrenches(self._first, pieces, self._powed, self.coef, self._parts, self._force, self._torque)
        self._swept, self._swept_prev = self._swept_prev, self._swept
        self._ready = True
        return self._result
