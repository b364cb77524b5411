"""Voxel buoyancy (Archimedes over voxels, thesis §4.2.5.2), all bodies in one numba call.

A voxel of edge s and inside fraction φ whose centre is h above the water (h = z - eta, world ENU)
displaces, with cutting, V = φ s² clamp(s/2 - h, 0, s): its submerged slab from the bottom face up
to the water, centred at z - (s/2 + h)/2 (the cube is treated as upright; the water is level across
it). Without cutting a voxel counts whole (φ s³, at its centre) when h < 0. The force ρ g k V acts
up at the volume-weighted centre of all submerged parts (k = `volume_scale`, e.g. mesh volume over
voxel volume), and the torque is taken about the centre of mass. (The seed applied the force at
the unweighted mean of the counted voxel centres.)

Use: voxels = VoxelSet([grid, ...]); c = voxels.world_centers(pos, rot); eta = ocean.elevation(c…);
res = voxels.compute(c, eta, com_world, rho, g, cut=True).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit

from usvsim.hydro.hydrostatics import transform_vertices
from usvsim.hydro.voxelize import VoxelGrid


@njit(cache=True)
def voxel_buoyancy(centers, fill, voxel_offsets, eta, com, size, scale, rho, g, cut,
                   force, torque, volume, cob):
    """Buoyancy of every body from its voxels.

    Inputs (world ENU, SI): centers (N,3) m voxel centres; fill (N,) inside fractions; voxel_offsets
    (nb+1,) uint64 (body b owns voxels offsets[b]:offsets[b+1]); eta (N,) water height at each
    centre m; com (nb,3) m; size (nb,) voxel edge m; scale (nb,) volume factor; rho kg/m³; g m/s²;
    cut (nb,) bool: body b counts partial voxels by slab volume (else all-or-nothing at h < 0).
    Outputs, overwritten: force (nb,3) N; torque (nb,3) N·m about the CoM; volume (nb,) m³ (scaled);
    cob (nb,3) m centre of buoyancy (= com when dry).
    """
    for b in range(voxel_offsets.shape[0] - 1):
        s = size[b]
        half, s2, s3 = 0.5 * s, s * s, s * s * s
        vol = mx = my = mz = 0.0
        for i in range(voxel_offsets[b], voxel_offsets[b + 1]):
            z = centers[i, 2]
            h = z - eta[i]
            if cut[b]:
                if h >= half:
                    continue
                if h <= -half:
                    dv, zc = s3, z
                else:
                    dv, zc = s2 * (half - h), z - 0.5 * (half + h)
            else:
                if h >= 0.0:
                    continue
                dv, zc = s3, z
            dv *= fill[i]
            vol += dv
            mx += dv * centers[i, 0]
            my += dv * centers[i, 1]
            mz += dv * zc
        _store(b, vol * scale[b], mx, my, mz, vol, com, rho * g, force, torque, volume, cob)


@njit(cache=True)
def _store(b, vol_scaled, mx, my, mz, vol, com, rho_g, force, torque, volume, cob):
    """Write body b's buoyancy: vertical force at the volume-weighted centre, torque about the CoM."""
    inv = 1.0 / vol if vol > 0.0 else 0.0
    cx = mx * inv if vol > 0.0 else com[b, 0]
    cy = my * inv if vol > 0.0 else com[b, 1]
    cz = mz * inv if vol > 0.0 else com[b, 2]
    fz = rho_g * vol_scaled
    force[b, 0], force[b, 1], force[b, 2] = 0.0, 0.0, fz
    rx, ry = cx - com[b, 0], cy - com[b, 1]
    torque[b, 0], torque[b, 1], torque[b, 2] = ry * fz, -rx * fz, 0.0
    volume[b] = vol_scaled
    cob[b, 0], cob[b, 1], cob[b, 2] = cx, cy, cz


@dataclass(frozen=True, slots=True)
class VoxelResult:
    """Views of a VoxelSet's output buffers (world ENU, SI), overwritten by its next compute()."""

    force: np.ndarray  # (nb,3) N
    torque: np.ndarray  # (nb,3) N·m about each CoM
    volume: np.ndarray  # (nb,) m³ displaced (after volume_scale)
    cob: np.ndarray  # (nb,3) m


class VoxelSet:
    """The voxel grids of all bodies, packed for the kernel.

    match_mesh_volume: scale each body's voxels so that, fully submerged, they displace exactly the
    mesh volume (per body; a grid's own Σ φ s³ otherwise).
    """

    def __init__(self, grids: Sequence[VoxelGrid], match_mesh_volume: bool | Sequence[bool] = True,
                 cut: bool | Sequence[bool] = True):  # fmt: skip
        nb = len(grids)
        match = [match_mesh_volume] * nb if isinstance(match_mesh_volume, bool) else list(match_mesh_volume)
        self.cut = np.array([cut] * nb if isinstance(cut, bool) else list(cut), dtype=np.bool_)
        counts = np.array([len(g.centers) for g in grids])
        self.n_bodies = nb
        self.offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.uint64)
        self.centers_body = np.ascontiguousarray(np.concatenate([g.centers for g in grids]).reshape(-1, 3))
        self.fill = np.ascontiguousarray(np.concatenate([g.fill for g in grids]).astype(float))
        self.voxel_body = np.repeat(np.arange(nb, dtype=np.int32), counts)
        self.size = np.array([g.size for g in grids], dtype=float)
        self.scale = np.array([g.mesh_volume / g.volume if m and g.volume > 0 else 1.0
                               for g, m in zip(grids, match)])  # fmt: skip
        self._world = np.zeros_like(self.centers_body)
        self._out = (np.zeros((nb, 3)), np.zeros((nb, 3)), np.zeros(nb), np.zeros((nb, 3)))
        self._result = VoxelResult(*self._out)

    def world_centers(self, pos: np.ndarray, rot: np.ndarray) -> np.ndarray:
        """Voxel centres (N,3) m ENU from body poses (nb,3) and rotations (nb,3,3) body → world.
        Returns an internal buffer, overwritten by the next call."""
        transform_vertices(self.centers_body, self.voxel_body, pos, rot, self._world)
        return self._world

    def compute(self, world_centers: np.ndarray, eta: np.ndarray, com_world: np.ndarray, rho: float,
                g: float, cut: bool | None = None) -> VoxelResult:
        """Buoyancy of every body; `cut` overrides the per-body setting given at construction."""
        cuts = self.cut if cut is None else np.full(self.n_bodies, bool(cut))
        voxel_buoyancy(world_centers, self.fill, self.offsets, eta, com_world, self.size, self.scale, rho, g,
                       cuts, *self._out)  # fmt: skip
        return self._result
