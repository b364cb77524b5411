"""Hydrostatics under flat water (no waves): the same integrals as `hull_hydrostatics`, with face clusters.

Each body's faces are grouped into small spatial clusters (recursive median bisection, at most
`CLUSTER_FACES` faces). Under a flat surface z = level the depth below the water is linear in the body-frame
position: d(v) = c0 - n·v, with v the vertex relative to the centre of mass in the body frame, n = R^T e_z
(the world's up in the body frame) and c0 = level - com_z. Every integrand of `hull_hydrostatics` over a fully
submerged face is then a polynomial of degree <= 2 in u = (c0, -n), whose coefficients are fixed per face and
add up per cluster (`_cluster_tensors`). Per step a cluster's body-frame bounding box decides:
- entirely above the surface: it contributes nothing (its faces' outputs are cleared once, not every step);
- entirely below: its sums come from its coefficients (about 150 flops for the whole cluster);
- crossing the surface: its faces go through the exact per-face clipping of `hull_hydrostatics`.
The results equal `hull_hydrostatics` with eta = level everywhere up to rounding (tests/hydro/test_flat.py:
forces, moments, volume, centre of buoyancy, areas, per-face outputs within 1e-9 relative).

Frames and units as in hydrostatics.py: world ENU (z up), metres, newtons; body frame FLU.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from usvsim.hydro.hydrostatics import (
    _add_face,
    _clear_segment,
    _cut_face,
    _depth_moments,
    _store_body,
    _store_segment,
)

CLUSTER_FACES = 16  # faces per cluster at most (measured: 8-32 cost about the same on the WAM-V; 16 the least)
WIDTH = 112  # coefficients per cluster: AF 12, AT 12, AQS 36, AE 48, AS 3, area 1
EPS_M = 1e-9  # a box must clear the surface by this much (m) to be taken as dry or wet without clipping
Z_WEIGHT = np.array([1.0, 1.0, 8.0])  # split across height first: thin horizontal layers are mostly dry or wet
UNKNOWN, DRY, WET, MIXED = 0, 1, 2, 3  # what a cluster's per-face outputs hold


def _clusters(centroids: np.ndarray, index: np.ndarray, size: int) -> list[np.ndarray]:
    """Face index groups of at most `size`, by recursive median bisection along the widest axis."""
    if len(index) <= size:
        return [index]
    c = centroids[index]
    axis = int(np.argmax((c.max(0) - c.min(0)) * Z_WEIGHT))
    order = index[np.argsort(c[:, axis], kind="stable")]
    half = len(order) // 2
    return _clusters(centroids, order[:half], size) + _clusters(centroids, order[half:], size)


def _cluster_tensors(v0: np.ndarray, v1: np.ndarray, v2: np.ndarray) -> np.ndarray:
    """The coefficients (WIDTH,) of one cluster's faces (k, 3) vertices, body frame relative to the CoM."""
    ones = np.ones((len(v0), 1))
    h0, h1, h2 = (np.hstack([ones, v]) for v in (v0, v1, v2))  # homogeneous: d = u · h
    ea, eb, ec = h0 + h1, h1 + h2, h2 + h0  # twice the depth at each edge midpoint (as a, b, c of _depth_moments)
    ma, mb, mc = v0 + v1, v1 + v2, v2 + v0
    s = np.cross(v1 - v0, v2 - v0)  # 2 A n
    wf = 2.0 * (ea + eb + ec)  # w = u · wf
    qf = np.einsum("fi,fl->fil", ma, ea) + np.einsum("fi,fl->fil", mb, eb) + np.einsum("fi,fl->fil", mc, ec)
    af = np.einsum("fk,fl->kl", s, wf)
    at = np.stack([np.cross(qf[:, :, l], s).sum(0) for l in range(4)], axis=1)  # (3, 4)
    aqs = np.einsum("fil,fj->lij", qf, s)
    quad = 0.5 * (np.einsum("fl,fm->flm", ea, ea) + np.einsum("fl,fm->flm", eb, eb) + np.einsum("fl,fm->flm", ec, ec))
    ae = np.einsum("fk,flm->klm", s, quad)
    area = 0.5 * np.linalg.norm(s, axis=1).sum()
    return np.concatenate([af.ravel(), at.ravel(), aqs.ravel(), ae.ravel(), s.sum(0), [area]])


class FlatClusters:
    """Cluster tables of a HullSet for `flat_hydrostatics` (body frame, relative to each body's CoM).

    Bodies with the same hull mesh (`HullSet.mesh_of`: byte-identical vertices and faces) and the same centre of mass
    share one set of tables (a *kind*): a fleet of one model reads one table (the WAM-V's 128 clusters: 120 kB) that
    stays in the core's caches, where a copy per body (11.5 MB at 100 WAM-Vs) was streamed from memory every step.
    Each body keeps only its clusters' states (`state`, a byte per cluster and body). A kind's tables are the numbers a
    table of one body would hold (the same clusters, faces and coefficients), so the sums are bit for bit the same."""

    def __init__(self, hulls, com_body, size: int = CLUSTER_FACES):
        com_body = np.asarray(com_body, float).reshape(-1, 3)
        kinds: dict[tuple[int, bytes], int] = {}  # (mesh, CoM bytes) → kind
        kind_of = [kinds.setdefault((int(hulls.mesh_of[b]), com_body[b].tobytes()), len(kinds))
                   for b in range(hulls.n_bodies)]  # fmt: skip
        self.kind_of = np.array(kind_of, dtype=np.uint64)
        rels, local_faces, groups, verts, kind_clusters = [], [], [], [], [0]
        for (m, com), _ in sorted(kinds.items(), key=lambda item: item[1]):
            mv0, mv1 = hulls.mesh_vert_offsets[m], hulls.mesh_vert_offsets[m + 1]
            mf0, mf1 = hulls.mesh_face_offsets[m], hulls.mesh_face_offsets[m + 1]
            rel = hulls.mesh_vertices[mv0:mv1] - np.frombuffer(com)
            faces = hulls.mesh_faces[mf0:mf1].astype(np.int64)  # indices into this mesh's vertices
            tri = rel[faces]
            mine = [np.sort(g) for g in _clusters(tri.mean(1), np.arange(len(faces)), size)] if len(faces) else []
            groups += [(tri, g) for g in mine]  # faces in mesh order within a cluster (memory locality)
            verts += [np.unique(faces[g]) for g in mine]  # each cluster's vertices
            rels.append(rel)
            local_faces.append(faces)
            kind_clusters.append(kind_clusters[-1] + len(mine))
        self.vertices = np.ascontiguousarray(np.concatenate(rels)) if rels else np.zeros((0, 3))
        self.kind_verts = np.concatenate([[0], np.cumsum([len(r) for r in rels])]).astype(np.uint64)
        self.mesh_faces = (np.ascontiguousarray(np.concatenate(local_faces)) if local_faces
                           else np.zeros((0, 3))).astype(np.uint64)  # fmt: skip
        self.kind_faces = np.concatenate([[0], np.cumsum([len(f) for f in local_faces])]).astype(np.uint64)
        self.kind_clusters = np.array(kind_clusters, dtype=np.uint64)
        per_body = np.diff(self.kind_clusters)[self.kind_of.astype(np.intp)] if len(kind_of) else np.zeros(0, int)
        self.body_clusters = np.concatenate([[0], np.cumsum(per_body)]).astype(np.uint64)  # rows of `state`
        self.ptr = np.concatenate([[0], np.cumsum([len(g) for _, g in groups])]).astype(np.uint64)
        self.faces = (np.concatenate([g for _, g in groups]) if groups else np.zeros(0)).astype(np.uint64)  # mesh-local
        self.vert_ptr = np.concatenate([[0], np.cumsum([len(v) for v in verts])]).astype(np.uint64)
        self.verts = (np.concatenate(verts) if verts else np.zeros(0)).astype(np.uint64)  # kind-local vertex indices
        nc = len(groups)
        self.coef = np.zeros((nc, WIDTH))
        self.box = np.zeros((nc, 6))  # centre (3), half extents (3), m
        for c, (tri, g) in enumerate(groups):
            t = tri[g]
            self.coef[c] = _cluster_tensors(t[:, 0], t[:, 1], t[:, 2])
            lo, hi = t.reshape(-1, 3).min(0), t.reshape(-1, 3).max(0)
            self.box[c, :3], self.box[c, 3:] = 0.5 * (lo + hi), 0.5 * (hi - lo)
        self.state = np.full(int(self.body_clusters[-1]), UNKNOWN, dtype=np.int8)  # per body and cluster
        rows = int(np.diff(self.kind_verts).max()) if rels else 0
        self._scratch = (np.zeros((rows, 3)), np.zeros((rows, 3)))  # a kind's rotated vertices: this thread, worker

    def invalidate(self) -> None:
        """Per-face outputs were written by someone else (the general kernel): rewrite them all next time."""
        self.state[:] = UNKNOWN

    def compute(self, hulls, rot, com_world, level: float, rho: float, g: float, out, overlap=None) -> None:
        """`flat_hydrostatics` of `hulls` (the HullSet these clusters were made for) into its output buffers `out`;
        with `overlap` (core/overlap.py) the bodies split where the faces halve, the first part on its worker thread
        (each body's sums are the same either way)."""
        args = (self.kind_of, self.kind_verts, self.kind_faces, self.kind_clusters, self.vertices, self.mesh_faces,
                hulls.face_area, hulls.face_offsets, self.body_clusters, self.ptr, self.faces, self.vert_ptr,
                self.verts, self.coef, self.box, self.state)  # fmt: skip
        tail = (rot, com_world, level, rho, g, *out)
        nb = hulls.n_bodies
        if overlap is None or nb < 2:
            flat_hydrostatics(0, nb, *args, self._scratch[0], *tail)
            return
        cut = hulls.split_body()
        wait = overlap.submit(flat_hydrostatics, 0, cut, *args, self._scratch[1], *tail)
        try:
            flat_hydrostatics(cut, nb, *args, self._scratch[0], *tail)
        finally:
            wait()


def use_flat(hulls, com_body: np.ndarray) -> None:
    """Prepare `hulls.compute_flat` (a HullSet) for bodies whose centres of mass are `com_body` (nb,3) m, body frame."""
    hulls.use_flat(FlatClusters(hulls, com_body))


@njit(cache=True)
def _add_cluster(coef, c, u0, u1, u2, u3, acc):
    """acc (WIDTH - nothing) += cluster c's sums evaluated at u: F_b (3), T_b (3), QS·(u) (9), ES (3), S (3),
    area: all body frame."""
    u = (u0, u1, u2, u3)
    k = 0
    for i in range(3):  # AF u
        s = 0.0
        for m in range(4):
            s += coef[c, k] * u[m]
            k += 1
        acc[i] += s
    for i in range(3):  # AT u
        s = 0.0
        for m in range(4):
            s += coef[c, k] * u[m]
            k += 1
        acc[3 + i] += s
    for m in range(4):  # Σ_l u_l AQS[l] (3x3)
        for ij in range(9):
            acc[6 + ij] += coef[c, k] * u[m]
            k += 1
    for i in range(3):  # u^T AE[i] u
        s = 0.0
        for m in range(4):
            r = 0.0
            for n in range(4):
                r += coef[c, k] * u[n]
                k += 1
            s += r * u[m]
        acc[15 + i] += s
    for i in range(3):
        acc[18 + i] += coef[c, k]
        k += 1
    acc[21] += coef[c, k]


@njit(cache=True, nogil=True)  # nogil: half the bodies may run on the overlap worker (FlatClusters.compute)
def flat_hydrostatics(b0, b1, kind_of, kind_verts, kind_faces, kind_clusters, verts_rel, mesh_faces, face_area,
                      face_offsets, body_clusters, cl_ptr, cl_faces, cl_vert_ptr, cl_verts, cl_coef, cl_box, cl_state,
                      r, rot, com, level, rho, g, force, torque, volume, cob, wetted_area, waterplane_area,
                      face_area_sub, seg, seg_count):  # fmt: skip
    """`hull_hydrostatics` of bodies b0:b1 for eta = level (m) at every vertex and no pressure heads (see the module
    text), from the shared tables of each body's kind (`FlatClusters`).

    verts_rel (kind vertices, 3) m: each kind's vertices in the body frame relative to the CoM, mesh_faces its faces
    (kind-local vertex indices); r (largest kind's vertex count, 3) scratch (kept between calls: a large array made
    per call would cost page faults every step); rot (nb,3,3) body → world; com (nb,3) m world. Outputs as
    `hull_hydrostatics`' (the face rows of body b at face_offsets[b] + its mesh-local face index; rows of clusters
    whose state did not change are kept)."""
    acc = np.zeros(22)
    for b in range(b0, b1):
        k = kind_of[b]
        v0, fl0, c0k, c1k = kind_verts[k], kind_faces[k], kind_clusters[k], kind_clusters[k + 1]
        fg0, s0 = face_offsets[b], body_clusters[b]  # the body's first face row and first cluster state
        cx, cy, cz = com[b, 0], com[b, 1], com[b, 2]
        r00, r01, r02 = rot[b, 0, 0], rot[b, 0, 1], rot[b, 0, 2]
        r10, r11, r12 = rot[b, 1, 0], rot[b, 1, 1], rot[b, 1, 2]
        n0, n1, n2 = rot[b, 2, 0], rot[b, 2, 1], rot[b, 2, 2]
        c0 = level - cz  # depth d(v) = c0 - n · v
        acc[:] = 0.0
        wet_clusters = 0
        fx = fy = fz = tx = ty = tz = vol = mx = my = mz = wet = awp = 0.0
        for c in range(c0k, c1k):
            cs = s0 + (c - c0k)  # this body's state of cluster c
            centre = n0 * cl_box[c, 0] + n1 * cl_box[c, 1] + n2 * cl_box[c, 2] - c0  # height above water
            spread = abs(n0) * cl_box[c, 3] + abs(n1) * cl_box[c, 4] + abs(n2) * cl_box[c, 5]
            if centre - spread > EPS_M:
                if cl_state[cs] != DRY:
                    for j in range(cl_ptr[c], cl_ptr[c + 1]):
                        f = fg0 + cl_faces[j]
                        face_area_sub[f] = 0.0
                        _clear_segment(seg, seg_count, f)
                    cl_state[cs] = DRY
                continue
            if centre + spread < -EPS_M:
                _add_cluster(cl_coef, c, c0, -n0, -n1, -n2, acc)
                wet_clusters += 1
                if cl_state[cs] != WET:
                    for j in range(cl_ptr[c], cl_ptr[c + 1]):
                        f = fg0 + cl_faces[j]
                        face_area_sub[f] = face_area[f]
                        _clear_segment(seg, seg_count, f)
                    cl_state[cs] = WET
                continue
            cl_state[cs] = MIXED
            for j in range(cl_vert_ptr[c], cl_vert_ptr[c + 1]):  # the cluster's vertices (shared ones: same values)
                v = cl_verts[j]
                x, y, z = verts_rel[v0 + v, 0], verts_rel[v0 + v, 1], verts_rel[v0 + v, 2]
                r[v, 0] = r00 * x + r01 * y + r02 * z
                r[v, 1] = r10 * x + r11 * y + r12 * z
                r[v, 2] = n0 * x + n1 * y + n2 * z
            for j in range(cl_ptr[c], cl_ptr[c + 1]):
                lf = cl_faces[j]
                f = fg0 + lf
                i0, i1, i2 = mesh_faces[fl0 + lf, 0], mesh_faces[fl0 + lf, 1], mesh_faces[fl0 + lf, 2]
                r0 = (r[i0, 0], r[i0, 1], r[i0, 2])
                r1 = (r[i1, 0], r[i1, 1], r[i1, 2])
                r2 = (r[i2, 0], r[i2, 1], r[i2, 2])
                h0, h1, h2 = r0[2] - c0, r1[2] - c0, r2[2] - c0
                n_below = (h0 <= 0.0) + (h1 <= 0.0) + (h2 <= 0.0)
                if n_below == 0 or (n_below == 1 and min(h0, h1, h2) == 0.0):
                    face_area_sub[f] = 0.0
                    if seg_count[f] != 0:  # a zero row stays (written out: see hull_hydrostatics)
                        for i in range(6):
                            seg[f, i // 3, i % 3] = 0.0
                        seg_count[f] = 0
                    continue
                if n_below == 3:
                    w, qx, qy, qz, e = _depth_moments(r0, r1, r2, -h0, -h1, -h2)
                    frac = 1.0
                    if seg_count[f] != 0:
                        for i in range(6):
                            seg[f, i // 3, i % 3] = 0.0
                        seg_count[f] = 0
                else:
                    terms, p, q = _cut_face(r0, r1, r2, h0, h1, h2, -h0, -h1, -h2, n_below)
                    w, qx, qy, qz, e, frac = terms
                    _store_segment(seg, seg_count, f, p, q, cx, cy, cz)
                running = (fx, fy, fz, tx, ty, tz, vol, mx, my, mz, awp)
                fx, fy, fz, tx, ty, tz, vol, mx, my, mz, awp = _add_face(
                    running, r0, r1, r2, w, qx, qy, qz, w, qx, qy, qz, e, frac
                )
                a_sub = frac * face_area[f]
                face_area_sub[f] = a_sub
                wet += a_sub
        if wet_clusters:  # the submerged clusters' sums, body frame → world
            bx, by, bz = acc[0], acc[1], acc[2]
            fx += r00 * bx + r01 * by + r02 * bz
            fy += r10 * bx + r11 * by + r12 * bz
            fz += n0 * bx + n1 * by + n2 * bz
            vol -= n0 * bx + n1 * by + n2 * bz
            bx, by, bz = acc[3], acc[4], acc[5]
            tx += r00 * bx + r01 * by + r02 * bz
            ty += r10 * bx + r11 * by + r12 * bz
            tz += n0 * bx + n1 * by + n2 * bz
            bx = acc[6] * n0 + acc[7] * n1 + acc[8] * n2  # (Σ q ⊗ S) n, body frame
            by = acc[9] * n0 + acc[10] * n1 + acc[11] * n2
            bz = acc[12] * n0 + acc[13] * n1 + acc[14] * n2
            mx -= r00 * bx + r01 * by + r02 * bz
            my -= r10 * bx + r11 * by + r12 * bz
            mz -= n0 * bx + n1 * by + n2 * bz + n0 * acc[15] + n1 * acc[16] + n2 * acc[17]
            awp -= n0 * acc[18] + n1 * acc[19] + n2 * acc[20]
            wet += acc[21]
        sums = (fx, fy, fz, tx, ty, tz, vol, mx, my, mz, wet, awp)
        _store_body(b, sums, (cx, cy, cz), rho * g, force, torque, volume, cob, wetted_area, waterplane_area)
