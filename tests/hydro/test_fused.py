"""The pass a body at a time (hydro/fused.py) and the per-face rows it keeps between calls (HullSet.face_state)
change where the work happens, not a single bit: every output equals the three separate passes (world vertices,
`pressure.hull_water`, `HullSet.compute`, which rewrites every per-face row)."""

from __future__ import annotations

import numpy as np
import trimesh

from usvsim.core.overlap import Overlap
from usvsim.hydro.fused import fused_hydrostatics
from usvsim.hydro.hydrostatics import HullSet, HydrostaticsResult
from usvsim.ocean import pressure, spectra
from usvsim.ocean.fft import FFTWaveField, cascade_sizes, directional_spectrum

RHO, G = 1025.0, 9.81
JONSWAP = directional_spectrum(lambda w: spectra.jonswap(w, 1.5, 7.0, 3.3), 0.4, 10.0)


def meshes():
    """Bodies 0, 2, 4 share a mesh (byte for byte), 1 and 3 are other meshes: a sphere, a box, a cylinder."""
    sphere = trimesh.creation.icosphere(2, radius=0.8)
    box = trimesh.creation.box((3.0, 1.2, 0.8))
    cyl = trimesh.creation.cylinder(radius=0.4, height=2.5, sections=24)
    return [(m.vertices.copy(), m.faces.copy()) for m in (sphere, box, sphere, cyl, sphere)]


def poses(rng, n, spread=0.4):
    """Positions straddling the surface (z within ±spread m) and random rotations (body → world)."""
    pos = np.column_stack([rng.uniform(-30, 30, n), rng.uniform(-30, 30, n), rng.uniform(-spread, spread, n)])
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    rot = np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
                    np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
                    np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], 1)  # fmt: skip
    return pos, np.ascontiguousarray(rot)


def three_passes(hulls, field, level, t, pos, rot, com):
    """The step as it was: world vertices, the one-call FFT water, the face kernel with every row rewritten."""
    verts = hulls.world_vertices(pos, rot)
    eta, head = np.empty(len(verts)), np.empty(len(verts))
    assert pressure.hull_water(field, verts, level, t, eta, head)
    out = hulls.compute(verts, eta, com, RHO, G, head)
    return verts.copy(), eta, head, out


def test_meshes_are_shared_byte_for_byte():
    hulls = HullSet(meshes())
    assert hulls.mesh_of.tolist() == [0, 1, 0, 2, 0]
    for b, m in enumerate(hulls.mesh_of):
        v0, v1 = hulls.vert_offsets[b], hulls.vert_offsets[b + 1]
        f0, f1 = hulls.face_offsets[b], hulls.face_offsets[b + 1]
        mv0, mv1 = hulls.mesh_vert_offsets[m], hulls.mesh_vert_offsets[m + 1]
        mf0, mf1 = hulls.mesh_face_offsets[m], hulls.mesh_face_offsets[m + 1]
        assert np.array_equal(hulls.vertices_body[v0:v1], hulls.mesh_vertices[mv0:mv1])
        assert np.array_equal(hulls.faces[f0:f1] - v0, hulls.mesh_faces[mf0:mf1])
        assert np.array_equal(hulls.face_area[f0:f1], hulls.mesh_face_area[mf0:mf1])
    moved = meshes()
    moved[2] = (moved[2][0] + 1e-12, moved[2][1])  # one bit off: its own mesh
    assert HullSet(moved).mesh_of.tolist() == [0, 1, 2, 3, 0]


def test_fused_pass_equals_the_three_passes_bit_for_bit():
    """Serial and split over two threads (the worker with its own node cache), keeping the vertices and heights
    or not; at several times (new blend states of the sea, stale node caches) and poses."""
    field = FFTWaveField(JONSWAP, cascade_sizes(70.0, 3, 64), np.random.default_rng(8), 64, ramp_time_s=1.0)
    rng = np.random.default_rng(5)
    ref_set, serial, split, lean, later = (HullSet(meshes()) for _ in range(5))
    overlap = Overlap()
    level = 0.2
    try:
        for t in (0.0, 0.4, 0.41, 3.7, 9.0):
            pos, rot = poses(rng, 5)
            pos[:, 2] += level
            com = pos + 0.01
            verts, eta, head, ref = three_passes(ref_set, field, level, t, pos, rot, com)
            assert 0 < ref.waterline_count.sum() < len(ref_set.faces)  # faces dry, wet and cut
            cases = ((serial, {}), (split, {"overlap": overlap}), (lean, {"keep": False}),
                     (later, {"overlap": overlap, "rows": False}))  # fmt: skip
            for hulls, kwargs in cases:
                e, h = np.full(len(eta), np.nan), np.full(len(eta), np.nan)
                p, r, c = pos.copy(), rot.copy(), com.copy()
                out = fused_hydrostatics(hulls, field, level, t, p, r, c, RHO, G, e, h, **kwargs)
                assert out is not None and (hulls._rows_later is not None) == (kwargs.get("rows") is False)
                p += 5.0  # the caller's state moves on, the sea too: rows made later are those of this call
                r[:] = r[:, ::-1]
                c -= 1.0
                field.update(t + 2.5)
                for name in HydrostaticsResult.FIELDS:
                    assert np.array_equal(getattr(out, name), getattr(ref, name)), name
                if kwargs.get("keep", True):
                    assert np.array_equal(hulls.world_buffer, verts)
                    assert np.array_equal(e, eta) and np.array_equal(h, head)
    finally:
        overlap.close()


def test_fused_pass_declines_what_it_cannot_do():
    """A choppy FFT sea (Newton inversion) is left to the separate passes: None, nothing written."""
    field = FFTWaveField(JONSWAP, cascade_sizes(70.0, 3, 64), np.random.default_rng(8), 64, choppiness=0.8)
    hulls = HullSet(meshes())
    pos, rot = poses(np.random.default_rng(1), 5)
    n = len(hulls.vertices_body)
    assert fused_hydrostatics(hulls, field, 0.0, 1.0, pos, rot, pos, RHO, G, np.empty(n), np.empty(n)) is None
    assert not hulls._out[2].any()


def test_rows_kept_between_calls_equal_rows_rewritten():
    """The pass leaves a dry or submerged face's rows alone when they already say so (HullSet.face_state): over poses
    that take faces from dry to cut to wet and back, with the other writers of the rows in between (compute_flat's
    clustered rows under flat water, `compute`, `compute_split`), and passes that leave the rows for later (`rows`
    False, as a wavy fleet's step: some read, some never), every result of the pass equals the three passes with all
    rows rewritten."""
    from usvsim.hydro.flat import use_flat

    field = FFTWaveField(JONSWAP, cascade_sizes(70.0, 3, 64), np.random.default_rng(4), 64)
    rng = np.random.default_rng(3)
    kept, ref_set = HullSet(meshes()), HullSet(meshes())
    use_flat(kept, np.zeros((5, 3)))
    overlap = Overlap()
    try:
        for k in range(40):
            pos, rot = poses(rng, 5, spread=1.2)
            t = 0.3 * k
            if k % 6 == 2:  # another writer now and then
                kept.compute_flat(rot, pos, 0.0, RHO, G)
                continue
            if k % 6 == 4:
                verts = kept.world_vertices(pos, rot)
                eta = 0.3 * np.sin(0.4 * verts[:, 0] + k)
                kept.compute(verts, eta, pos, RHO, G) if k % 12 == 4 else kept.compute_split(overlap, verts, eta, pos,
                                                                                             RHO, G)  # fmt: skip
                continue
            n = len(kept.vertices_body)
            rows = k % 5 != 1 and k % 7 != 3
            out = fused_hydrostatics(kept, field, 0.0, t, pos, rot, pos, RHO, G, np.empty(n), np.empty(n), overlap,
                                     rows=rows)  # fmt: skip
            ref = three_passes(ref_set, field, 0.0, t, pos, rot, pos)[3]
            assert out is not None
            if k % 5 == 1:  # left for later and never read: the next writer's rows are all that count
                assert kept._rows_later is not None
                continue
            for name in HydrostaticsResult.FIELDS:
                assert np.array_equal(getattr(out, name), getattr(ref, name)), (k, name)
    finally:
        overlap.close()
