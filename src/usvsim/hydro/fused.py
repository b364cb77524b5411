"""Hull vertices, FFT water and hydrostatics of a wavy fleet in one pass, a body at a time.

A wavy step otherwise makes three passes over every hull of the scene: the world vertices
(`hydrostatics.transform_vertices`), the surface height and Froude–Krylov head at each of them
(`ocean.pressure.hull_water`), then the faces (`hydrostatics.hull_hydrostatics`). At 200 WAM-Vs (112,800
vertices, 224,000 faces) the arrays between the passes (world vertices 2.7 MB, heights and heads 1.8 MB) and the
per-body copies of one mesh (7 MB of vertices, faces and areas) are streamed through the caches every step. Here
each body's vertices are made from its mesh (`HullSet.mesh_*`: bodies with byte-identical hulls share one copy),
their water queried and that body's faces integrated before the next body, in scratch rows that stay in the
core's caches; the pass is split over the two cores as `HullSet.compute_split` splits the faces (the worker with
its own node cache of the sea), so the water query runs on both cores too.

The same operations make the same numbers: the transform is `transform_vertices`' expression per vertex, the
water `pressure.hull_water_rows` over the body's rows (its node cache and last-cell corners carried from body to
body, as in one pass), the faces `hydrostatics._body_faces` (hull_hydrostatics' own loop, inlined) over that
body. Every output of the HullSet, and the world vertices, heights and heads when they are kept, are bit for bit
those of the three passes (tests/hydro/test_fused.py, tests/sim/test_marine_models.py).

Frames and units: world ENU (z up), metres, newtons; the FFT sea's heights relative to still water at `level`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from usvsim.hydro.hydrostatics import HullSet, HydrostaticsResult, _body_faces, _store_body
from usvsim.ocean.fft import FFTWaveField
from usvsim.ocean.pressure import height_decay_wavenumbers, hull_water_rows, serial_fft, water_scratch


@njit(cache=True, nogil=True)  # nogil: half the bodies may run on the overlap worker (core/overlap.py)
def fused_hull_pass(b0, b1, mesh_of, mesh_vert_offsets, mesh_face_offsets, mesh_vertices, mesh_faces, mesh_face_area,
                    vert_offsets, face_offsets, pos, rot, keep, world, eta, head, level, geo, wts, inv_cells, decay_k,
                    cache, stamp, now, com, rho, g, force, torque, volume, cob, wetted_area, waterplane_area,
                    face_area_sub, seg, seg_count, face_state, rows, own_world, own_eta, own_head, last, corners,
                    hb):  # fmt: skip
    """Bodies b0:b1, each in turn from its mesh (HullSet.mesh_*): its world vertices (m), the surface z and pressure
    head at them (`hull_water_rows`, node cache (cache, stamp, now) of the FFT sea), then its hydrostatics
    (`hydrostatics._body_faces`, hull_hydrostatics' face loop, over its faces: outputs in row b and in its face
    rows; `rows` False: the face rows and states are left untouched). `keep`: the vertices, heights and heads go to their rows of `world`, `eta` and `head` (Nv rows, for
    whoever reads them next); else into the scratch rows own_world, own_eta, own_head (the largest mesh's vertex
    count), which stay in the caches. last, corners, hb: `pressure.water_scratch` arrays (any contents)."""
    for b in range(last.shape[0]):  # no cell's corners held yet (as a fresh `water_scratch`)
        last[b, 0] = last[b, 1] = -1
    fk = head.shape[0] > 0
    for b in range(b0, b1):
        m = mesh_of[b]
        mv0, mf0, mf1 = mesh_vert_offsets[m], np.uint64(mesh_face_offsets[m]), np.uint64(mesh_face_offsets[m + 1])
        nv = mesh_vert_offsets[m + 1] - mv0
        if keep:
            verts, h_eta, h_head, v0 = world, eta, head, np.int64(vert_offsets[b])
        else:
            verts, h_eta, h_head, v0 = own_world, own_eta, own_head, np.int64(0)
        r00, r01, r02 = rot[b, 0, 0], rot[b, 0, 1], rot[b, 0, 2]  # transform_vertices, the same expressions
        r10, r11, r12 = rot[b, 1, 0], rot[b, 1, 1], rot[b, 1, 2]
        r20, r21, r22 = rot[b, 2, 0], rot[b, 2, 1], rot[b, 2, 2]
        px, py, pz = pos[b, 0], pos[b, 1], pos[b, 2]
        for v in range(nv):
            x, y, z = mesh_vertices[mv0 + v, 0], mesh_vertices[mv0 + v, 1], mesh_vertices[mv0 + v, 2]
            verts[v0 + v, 0] = r00 * x + r01 * y + r02 * z + px
            verts[v0 + v, 1] = r10 * x + r11 * y + r12 * z + py
            verts[v0 + v, 2] = r20 * x + r21 * y + r22 * z + pz
        hull_water_rows(verts, v0, v0 + nv, level, geo, wts, inv_cells, decay_k, h_eta, h_head, cache, stamp, now, last,
                        corners, hb)  # fmt: skip
        cx, cy, cz = com[b, 0], com[b, 1], com[b, 2]
        sums = _body_faces(verts, mesh_faces, mesh_face_area, mf0, mf1, np.uint64(v0), face_offsets[b] - mf0, h_eta,
                           h_head, fk, cx, cy, cz, face_area_sub, seg, seg_count, face_state, rows)  # fmt: skip
        _store_body(b, sums, (cx, cy, cz), rho * g, force, torque, volume, cob, wetted_area, waterplane_area)


def _scratch(hulls: HullSet, bands: int, worker: bool) -> tuple[np.ndarray, ...]:
    """The scratch arrays of one thread's `fused_hull_pass` (kept on the HullSet: made per call, they were 7 small
    allocations a step): one body's vertices, heights and heads (the largest mesh), `water_scratch` for `bands`."""
    name = "_fused_scratch_worker" if worker else "_fused_scratch"
    kept = hulls.__dict__.get(name)
    if kept is None or kept[0] != bands:
        n = int(np.diff(hulls.mesh_vert_offsets).max())
        kept = hulls.__dict__[name] = (bands, (np.zeros((n, 3)), np.zeros(n), np.zeros(n), *water_scratch(bands)))
    return kept[1]


def _second_node_cache(waves: FFTWaveField) -> tuple[np.ndarray, np.ndarray]:
    """A node cache (heights, stamps) of `waves`' shape for the overlap worker's half of the bodies: its own, so the
    two threads never write one entry; stamped with the sea's own blend-state numbers (`node_cache`), so an entry
    is current exactly when the sea's would be. Values are a function of the node and the blend state alone: the
    same bits whichever cache holds them."""
    kept = waves.__dict__.get("_fused_second_node_cache")
    if kept is None:
        heights, stamps = waves.node_cache()[:2]
        kept = waves.__dict__["_fused_second_node_cache"] = (np.zeros_like(heights), np.zeros_like(stamps))
    return kept


def fused_hydrostatics(hulls: HullSet, waves, level: float, t: float, pos: np.ndarray, rot: np.ndarray,
                       com_world: np.ndarray, rho: float, g: float, eta: np.ndarray, head: np.ndarray,
                       overlap=None, keep: bool = True, rows: bool = True) -> HydrostaticsResult | None:  # fmt: skip
    """`hulls.compute(hulls.world_vertices(pos, rot), eta, com_world, rho, g, head)` with eta and head from
    `pressure.hull_water(waves, ..., level, t, eta, head)`, in one pass a body at a time, bit for bit; every
    vertex Froude–Krylov. `overlap` (core/overlap.Overlap): the bodies split where the faces halve, the first part
    on its worker (as `HullSet.compute_split`). None (nothing done) unless `waves` is an FFT sea without
    displacement answered by the serial kernels. pos, rot, com_world: (nb,3), (nb,3,3) body → world, (nb,3) m;
    eta, head: (Nv,) buffers, filled with the world vertices (`hulls.world_buffer`) when `keep`; without `keep`
    they are left as they were (each body's rows live in scratch rows while it is done). `rows` False: the per-face
    rows are made when the result's rows are first read (`HullSet.rows_later`: this pass again at these poses and
    this time, serial, the same bits); a wavy fleet's step reads none of them, and writing them every step (the
    rows of the ~15 % of faces the waterline cuts, 1.9 MB at 200 WAM-Vs) pushed the fleet out of the caches."""
    n = len(hulls.vertices_body)
    if not serial_fft(waves, n) or len(eta) != n or len(head) != n:
        return None
    wts = waves.update(t)
    cache, stamp, now = waves.node_cache()
    sea = (float(level), waves.geometry.tiles, wts, waves.inv_cells, height_decay_wavenumbers(waves))
    mesh = (hulls.mesh_of, hulls.mesh_vert_offsets, hulls.mesh_face_offsets, hulls.mesh_vertices, hulls.mesh_faces,
            hulls.mesh_face_area, hulls.vert_offsets, hulls.face_offsets, pos, rot, keep, hulls.world_buffer, eta,
            head)  # fmt: skip
    rest = (com_world, rho, g, *hulls._out, hulls.face_state(), rows)
    nb, bands = hulls.n_bodies, len(waves.inv_cells)
    if overlap is None or nb < 2:
        fused_hull_pass(0, nb, *mesh, *sea, cache, stamp, now, *rest, *_scratch(hulls, bands, False))
    else:
        cut = hulls.split_body()
        wait = overlap.submit(fused_hull_pass, 0, cut, *mesh, *sea, *_second_node_cache(waves), now, *rest,
                              *_scratch(hulls, bands, True))  # fmt: skip
        try:
            fused_hull_pass(cut, nb, *mesh, *sea, cache, stamp, now, *rest, *_scratch(hulls, bands, False))
        finally:
            wait()
    hulls.rows_written(tracked=True)
    if not rows:
        pos, rot, com_world = pos.copy(), rot.copy(), com_world.copy()  # the state moves on with the step
        hulls.rows_later(lambda: fused_hydrostatics(hulls, waves, level, t, pos, rot, com_world, rho, g, eta, head,
                                                    keep=False))  # fmt: skip
    return hulls._result
