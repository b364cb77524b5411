"""Hull hydrostatics: usvsim's numba kernels vs a vectorized-NumPy implementation, same run.

Workload: icosphere R = 0.5 m, 5120 triangles, half submerged (centre 2 mm above flat water,
rolled 0.1 rad so the waterline cuts faces generically). One call = transform the hull to world
+ exact hydrostatics (force, torque, volume, centre of buoyancy, wetted and waterplane area,
per-face submerged area, waterline segments). The kernels are serial (one core; no numba
threading involved). Median of many calls after warm-up (best of 5 batches), µs per call, with the
Python call overhead of `HullSet.world_vertices` + `HullSet.compute`.
Also reported: the ratio to the seed simulator's 4787 µs per call (Unity, 5120 triangles,
triangle submersion; hardware unknown).

    python benchmarks/bench_hydrostatics.py [--calls 20000]
Writes benchmarks/results/hydrostatics.json.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

import numpy as np
import trimesh

from usvsim.hydro.hydrostatics import HullSet

RESULTS = Path(__file__).parent / "results" / "hydrostatics.json"
SEED_US_5120 = 4787.0
RHO, G = 1000.0, 9.81


def _moments(p: np.ndarray, d: np.ndarray):
    """12 × per-area depth integrals of triangles p (n,3,3), depths d (n,3): W, Q (n,3), E."""
    mid = d + np.roll(d, -1, axis=1)  # twice the depth at edge midpoints (0-1, 1-2, 2-0)
    q = np.einsum("nkc,nk->nc", p + np.roll(p, -1, axis=1), mid)
    return 2.0 * mid.sum(axis=1), q, 0.5 * (mid**2).sum(axis=1)


def _cut(p, q, hp, hq):
    inv = 1.0 / (hp - hq)
    t, u = hp * inv, -hq * inv
    return u[:, None] * p + t[:, None] * q, t, u


def numpy_hydrostatics(verts_body, faces, face_area, pos, rot, eta, com, rho, g):
    """Baseline: the same exact computation for one body with whole-array NumPy operations."""
    world = verts_body @ rot.T + pos
    h = (world[:, 2] - eta)[faces]
    r = (world - com)[faces]
    below = h <= 0.0
    n_below = below.sum(axis=1)
    cut = ((n_below == 1) & (h.min(axis=1) < 0.0)) | (n_below == 2)
    full = n_below == 3
    apex = np.where(n_below == 2, np.argmax(~below, axis=1), np.argmax(below, axis=1))[cut]
    order = (apex[:, None] + np.arange(3)) % 3
    rc_, hc_ = np.take_along_axis(r[cut], order[:, :, None], axis=1), np.take_along_axis(h[cut], order, 1)
    ra, rb, rc = rc_[:, 0], rc_[:, 1], rc_[:, 2]
    ha, hb, hc = hc_[:, 0], hc_[:, 1], hc_[:, 2]
    n = len(faces)
    W, Q, E, frac = np.zeros(n), np.zeros((n, 3)), np.zeros(n), np.zeros(n)
    W[full], Q[full], E[full] = _moments(r[full], -h[full])
    frac[full] = 1.0
    seg = np.zeros((n, 2, 3))
    # one vertex above: quad (b, c, I_c, I_b) = (b, c, I_c) u_c + (b, I_c, I_b) s_c u_b
    one = n_below[cut] == 2
    ib, _, ub = _cut(ra[one], rb[one], ha[one], hb[one])
    ic, sc, uc = _cut(ra[one], rc[one], ha[one], hc[one])
    zero = np.zeros_like(uc)
    w1, q1, e1 = _moments(np.stack([rb[one], rc[one], ic], 1), np.stack([-hb[one], -hc[one], zero], 1))
    w2, q2, e2 = _moments(np.stack([rb[one], ic, ib], 1), np.stack([-hb[one], zero, zero], 1))
    f1, f2 = uc, sc * ub
    idx = np.flatnonzero(cut)[one]
    W[idx], E[idx], frac[idx] = f1 * w1 + f2 * w2, f1 * e1 + f2 * e2, f1 + f2
    Q[idx] = f1[:, None] * q1 + f2[:, None] * q2
    seg[idx] = np.stack([ic, ib], 1) + com
    # two vertices above: triangle (a, J_b, J_c) t_b t_c
    two = ~one
    jb, tb, _ = _cut(ra[two], rb[two], ha[two], hb[two])
    jc, tc, _ = _cut(ra[two], rc[two], ha[two], hc[two])
    zero = np.zeros_like(tb)
    w, q, e = _moments(np.stack([ra[two], jb, jc], 1), np.stack([-ha[two], zero, zero], 1))
    idx = np.flatnonzero(cut)[two]
    f = tb * tc
    W[idx], Q[idx], E[idx], frac[idx] = f * w, f[:, None] * q, f * e, f
    seg[idx] = np.stack([jb, jc], 1) + com
    C = np.cross(r[:, 1] - r[:, 0], r[:, 2] - r[:, 0])
    k = -rho * g / 24.0
    vol24 = -(W * C[:, 2]).sum()
    moment = -((Q + E[:, None] * [0.0, 0.0, 1.0]) * C[:, 2:3]).sum(axis=0)
    return {
        "force": k * (W[:, None] * C).sum(axis=0),
        "torque": k * np.cross(Q, C).sum(axis=0),
        "volume": vol24 / 24.0,
        "cob": com + moment / vol24,
        "wetted_area": (frac * face_area).sum(),
        "waterplane_area": -0.5 * (frac * C[:, 2]).sum(),
        "face_submerged_area": frac * face_area,
        "waterline_segments": seg,
    }


def median_us(fn, calls: int, batches: int = 5) -> float:
    """Median µs per call over `calls` calls after warm-up; the lowest of `batches` batch medians
    (other processes on the 2 cores only ever slow a batch down)."""
    for _ in range(max(10, calls // 100)):
        fn()
    medians = []
    for _ in range(batches):
        times = np.empty(max(1, calls // batches))
        for i in range(len(times)):
            t0 = time.perf_counter()
            fn()
            times[i] = time.perf_counter() - t0
        medians.append(np.median(times))
    return float(min(medians) * 1e6)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=20000)
    args = parser.parse_args()
    mesh = trimesh.creation.icosphere(subdivisions=4, radius=0.5)
    hulls = HullSet([(mesh.vertices, mesh.faces)])
    c, s = np.cos(0.1), np.sin(0.1)
    rot = np.array([[[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]])
    pos = np.array([[0.0, 0.0, 0.002]])
    eta = np.zeros(len(mesh.vertices))
    com = pos.copy()

    def kernel():
        return hulls.compute(hulls.world_vertices(pos, rot), eta, com, RHO, G)

    def baseline():
        return numpy_hydrostatics(
            hulls.vertices_body,
            hulls.faces.astype(np.intp),
            hulls.face_area,
            pos[0],
            rot[0],
            eta,
            com[0],
            RHO,
            G,
        )

    res, ref = kernel(), baseline()
    for name, value in ref.items():  # the baseline computes the same thing
        ours = getattr(res, name)
        ours = ours if name.startswith(("face_", "waterline_")) else ours[0]
        np.testing.assert_allclose(ours, value, rtol=1e-9, atol=1e-12, err_msg=name)
    t_kernel = median_us(kernel, args.calls)
    t_transform = median_us(lambda: hulls.world_vertices(pos, rot), args.calls)
    world = hulls.world_vertices(pos, rot)
    t_hydro = median_us(lambda: hulls.compute(world, eta, com, RHO, G), args.calls)
    t_numpy = median_us(baseline, max(200, args.calls // 50))
    box = trimesh.creation.box(extents=(2.0, 1.0, 1.0))  # 12 triangles: the Python call overhead
    tiny = HullSet([(box.vertices, box.faces)])
    t_tiny = median_us(lambda: tiny.compute(tiny.world_vertices(pos, rot), eta[:8], com, RHO, G), args.calls)
    report = {
        "machine": f"{platform.machine()}, {os.cpu_count()} cores",
        "workload": "icosphere R=0.5 m, 5120 triangles, half submerged, 1 body",
        "cut_faces": int(res.waterline_count.sum()),
        "volume_m3": float(res.volume[0]),
        "us_per_call": {
            "usvsim (transform + hydrostatics)": round(t_kernel, 2),
            "usvsim transform only": round(t_transform, 2),
            "usvsim hydrostatics only": round(t_hydro, 2),
            "usvsim, 12-triangle box (call overhead)": round(t_tiny, 2),
            "numpy baseline": round(t_numpy, 1),
            "seed (Unity, reported)": SEED_US_5120,
        },
        "speedup_vs_numpy": round(t_numpy / t_kernel, 1),
        "speedup_vs_seed": round(SEED_US_5120 / t_kernel, 1),
        "triangles_per_s": round(len(mesh.faces) / (t_kernel * 1e-6)),
        "target_us": 50.0,
        "meets_target": t_kernel <= 50.0,
    }
    print(f"{report['workload']} ({report['cut_faces']} faces cut by the waterline)")
    print(f"{'implementation':40s} {'µs/call':>10s}")
    for name, us in report["us_per_call"].items():
        print(f"{name:40s} {us:10.2f}")
    print(
        f"speedup vs numpy baseline: {report['speedup_vs_numpy']:.1f}x; "
        f"vs seed's 4787 µs: {report['speedup_vs_seed']:.0f}x; "
        f"{report['triangles_per_s'] / 1e6:.0f} M triangles/s"
    )
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    RESULTS.write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
