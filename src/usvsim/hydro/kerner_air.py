"""Air drag (physics.md §1.8) on the whole dry faces of each hull, summed in the body frame.

A whole dry face needs only its centroid, unit normal and area, which are fixed in the body frame,
so they are tabulated once (`dry_face_table`) and the per-step sum is a loop over contiguous rows
with no gathers: numba vectorizes it (SIMD; the sums are reassociated, which changes them by
rounding only). Cut faces keep their dry remainder in the face loop of `kerner_kernels`.

The body's rotation is recovered each step from three of its hull vertices (`anchor_frames`):
R = W B⁻¹, with B = [u, v, u × v] the anchor edges in the body frame and W the same in the world;
the body-frame origin then sits at x_a - R p_a. This keeps the kernels' inputs the world vertices
alone, and is exact to rounding for a rigid hull.
Frames and units: world ENU, body frame of `HullSet.vertices_body`, SI.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

# Rows of the dry-face table: centroid (body frame, m), unit outward normal (body frame), area m²
D_CX, D_CY, D_CZ, D_NX, D_NY, D_NZ, D_AREA = 0, 1, 2, 3, 4, 5, 6
N_DRY_ROWS = 7


def dry_face_table(vertices_body: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(N_DRY_ROWS, Nf) table of body-frame centroids, unit normals (0 for area 0) and areas."""
    tri = vertices_body[faces.astype(np.intp)]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    twice_area = np.linalg.norm(cross, axis=1)
    normal = cross / np.where(twice_area > 0.0, twice_area, 1.0)[:, None]
    return np.ascontiguousarray(np.vstack([tri.mean(axis=1).T, normal.T, 0.5 * twice_area]))


def anchor_frames(vertices_body: np.ndarray, vert_offsets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per body: anchor vertex indices (nb,3) int64 (a, b, c: a triangle as large as a greedy search
    finds) and (nb,12) = B⁻¹ (row-major 3x3) and the anchor a's body-frame position p_a."""
    nb = len(vert_offsets) - 1
    anchors, frames = np.zeros((nb, 3), dtype=np.int64), np.zeros((nb, 12))
    for k in range(nb):
        lo, hi = int(vert_offsets[k]), int(vert_offsets[k + 1])
        p = vertices_body[lo:hi]
        a = int(np.argmax(np.linalg.norm(p - p.mean(axis=0), axis=1)))
        b = int(np.argmax(np.linalg.norm(p - p[a], axis=1)))
        c = int(np.argmax(np.linalg.norm(np.cross(p[b] - p[a], p - p[a]), axis=1)))
        u, v = p[b] - p[a], p[c] - p[a]
        basis = np.column_stack([u, v, np.cross(u, v)])
        if abs(np.linalg.det(basis)) < 1e-12 * max(np.linalg.norm(u), 1e-300) ** 3:
            raise ValueError(f"hull {k}: its vertices are collinear, no body frame can be recovered")
        anchors[k] = (lo + a, lo + b, lo + c)
        frames[k, :9], frames[k, 9:] = np.linalg.inv(basis).ravel(), p[a]
    return anchors, frames


@njit(cache=True, inline="always")
def _sub(vertices, i, j):
    return vertices[i, 0] - vertices[j, 0], vertices[i, 1] - vertices[j, 1], vertices[i, 2] - vertices[j, 2]


@njit(cache=True)
def body_rotation(b, vertices, anchors, frames):
    """Rotation body → world (row-major 9-tuple) and body-origin position (world, m) of body b."""
    a = anchors[b, 0]
    u, v = _sub(vertices, anchors[b, 1], a), _sub(vertices, anchors[b, 2], a)
    w = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    m = frames[b]
    rot = (u[0] * m[0] + v[0] * m[3] + w[0] * m[6], u[0] * m[1] + v[0] * m[4] + w[0] * m[7],
           u[0] * m[2] + v[0] * m[5] + w[0] * m[8], u[1] * m[0] + v[1] * m[3] + w[1] * m[6],
           u[1] * m[1] + v[1] * m[4] + w[1] * m[7], u[1] * m[2] + v[1] * m[5] + w[1] * m[8],
           u[2] * m[0] + v[2] * m[3] + w[2] * m[6], u[2] * m[1] + v[2] * m[4] + w[2] * m[7],
           u[2] * m[2] + v[2] * m[5] + w[2] * m[8])  # fmt: skip
    pa = (m[9], m[10], m[11])
    origin = (vertices[a, 0] - (rot[0] * pa[0] + rot[1] * pa[1] + rot[2] * pa[2]),
              vertices[a, 1] - (rot[3] * pa[0] + rot[4] * pa[1] + rot[5] * pa[2]),
              vertices[a, 2] - (rot[6] * pa[0] + rot[7] * pa[1] + rot[8] * pa[2]))  # fmt: skip
    return rot, origin


@njit(cache=True, inline="always")
def _to_body(rot, x):
    """R^T x for a world vector x."""
    return (rot[0] * x[0] + rot[3] * x[1] + rot[6] * x[2], rot[1] * x[0] + rot[4] * x[1] + rot[7] * x[2],
            rot[2] * x[0] + rot[5] * x[1] + rot[8] * x[2])  # fmt: skip


@njit(cache=True, inline="always")
def _to_world(rot, x):
    """R x for a body-frame vector x."""
    return (rot[0] * x[0] + rot[1] * x[1] + rot[2] * x[2], rot[3] * x[0] + rot[4] * x[1] + rot[5] * x[2],
            rot[6] * x[0] + rot[7] * x[1] + rot[8] * x[2])  # fmt: skip


# Pure reduction over contiguous rows: numba/LLVM vectorizes it once reassociation is allowed.
@njit(cache=True, fastmath={"reassoc", "nsz"})
def _dry_sums(f0, f1, dry, table, com_b, v_b, om_b, rho_c):
    """Body-frame air force and torque about the CoM on the faces f0:f1 with dry[f] = 1."""
    fx = fy = fz = tx = ty = tz = 0.0
    for f in range(f0, f1):
        rx, ry, rz = table[D_CX, f] - com_b[0], table[D_CY, f] - com_b[1], table[D_CZ, f] - com_b[2]
        vx = v_b[0] + om_b[1] * rz - om_b[2] * ry
        vy = v_b[1] + om_b[2] * rx - om_b[0] * rz
        vz = v_b[2] + om_b[0] * ry - om_b[1] * rx
        into = vx * table[D_NX, f] + vy * table[D_NY, f] + vz * table[D_NZ, f] > 0.0
        s = -0.5 * rho_c * table[D_AREA, f] * math.sqrt(vx * vx + vy * vy + vz * vz) * dry[f]
        s = s if into else 0.0
        px, py, pz = s * vx, s * vy, s * vz
        fx += px
        fy += py
        fz += pz
        tx += ry * pz - rz * py
        ty += rz * px - rx * pz
        tz += rx * py - ry * px
    return fx, fy, fz, tx, ty, tz


@njit(cache=True)
def dry_air_wrench(b, f0, f1, dry, table, vertices, anchors, frames, com, vel_rel_air, omega, rho_c):
    """Air drag on body b's whole dry faces (dry[f] = 1 for f in f0:f1, else 0): world force N and
    torque N·m about the CoM. vel_rel_air (3-tuple): CoM velocity minus wind, m/s; omega (nb,3)."""
    rot, origin = body_rotation(b, vertices, anchors, frames)
    com_b = _to_body(rot, (com[b, 0] - origin[0], com[b, 1] - origin[1], com[b, 2] - origin[2]))
    v_b, om_b = _to_body(rot, vel_rel_air), _to_body(rot, (omega[b, 0], omega[b, 1], omega[b, 2]))
    s = _dry_sums(f0, f1, dry, table, com_b, v_b, om_b, rho_c)
    return _to_world(rot, s[:3]) + _to_world(rot, s[3:])
