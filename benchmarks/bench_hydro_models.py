"""Hydro model kernels: µs per call against a plain-NumPy baseline measured in the same run, and the seed.

    python benchmarks/bench_hydro_models.py
Workloads (one core unless stated; numba kernels are serial unless stated):
1. Kerner full set (viscous, pressure/suction, slamming, air) on a 5120-triangle hull half under
   water, moving and turning, with per-vertex water velocities; also with the hydrostatics added.
   Baseline: NumPy over whole triangles (no cutting: faces with a submerged centroid count whole,
   the rest get air drag) — less work than the kernel, so its ratio understates the speed-up.
2. Voxel buoyancy with cutting, 4140 voxels (R = 0.5 m sphere, s = 0.05 m, the seed's 4154 case):
   centre transform + kernel. Baseline: the same arithmetic vectorized in NumPy.
3. 100 hulls of 396 triangles each under Kerner forces (hydrostatics + all Kerner terms), one call;
   the whole step and the Kerner share, with the Kerner bodies on 1 thread and on 2 threads
   (KernerForces(parallel=True), prange over bodies; hydrostatics stays serial).
Previous implementation (per-face pow, normals by division, no per-body bounds; this machine,
benchmarks/results/hydro_models.json before the rewrite): Kerner 5120 292 µs, fleet step 3004 µs.
Seed (Unity/C#, seed-repository.md §6, hardware unknown): triangle submersion 5120 tris 4787 µs;
voxel cut 4154 voxels 954 µs, not cut 879 µs.
Writes benchmarks/results/hydro_models.json.
"""

from __future__ import annotations

import json
import os
import platform
import time
from pathlib import Path

# OpenMP threads sleep at barriers instead of spinning: on a shared 2-core machine a spinning
# worker waiting for a descheduled one made the 2-thread fleet step ~10x slower (set before numba).
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import numpy as np
import trimesh

from usvsim.config.hydro_models import KernerHydrodynamics
from usvsim.hydro.hydrostatics import HullSet
from usvsim.hydro.kerner import KernerForces
from usvsim.hydro.voxelize import voxelize
from usvsim.hydro.voxels import VoxelSet
from usvsim.vessels.hulls import loft

RESULTS = Path(__file__).parent / "results" / "hydro_models.json"
SEED_US = {"triangle_submersion_5120": 4787.0, "voxel_cut_4154": 954.0, "voxel_not_cut_4154": 879.0}
PREVIOUS_US = {"kerner_5120": 292.0, "fleet_step": 3004.0}  # before the Kerner kernel rewrite, same machine


def best_us(fn, loops: int, repeats: int = 5) -> float:
    fn()
    best = float("inf")
    for _ in range(repeats):
        t = time.perf_counter()
        for _ in range(loops):
            fn()
        best = min(best, (time.perf_counter() - t) / loops)
    return best * 1e6


def numpy_kerner(tri, water, com, v, w, wind, rho=1025.0, c_f=0.003):
    """Baseline: per whole triangle, viscous + pressure (pressure side only) + air, NumPy."""
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    cr = np.cross(e1, e2)
    area = 0.5 * np.linalg.norm(cr, axis=1)
    n = cr / (2 * area[:, None])
    c = tri.mean(axis=1)
    r = c - com
    vel = v + np.cross(w, r)
    wet = c[:, 2] < 0
    vr = np.where(wet[:, None], vel - water, vel - wind)
    speed = np.linalg.norm(vr, axis=1)
    vn = np.einsum("ij,ij->i", vr, n)
    vt = vr - vn[:, None] * n
    ft = -0.5 * rho * c_f * area[:, None] * speed[:, None] ** 2 * vt / np.maximum(np.linalg.norm(vt, axis=1), 1e-12)[:, None]
    cos = np.clip(vn / np.maximum(speed, 1e-12), 0, 1)
    fp = -((100 * speed + 100 * speed**2) * area * cos**0.4)[:, None] * n
    fa = -0.5 * 1.225 * 0.8 * (area * speed)[:, None] * vr * (vn > 0)[:, None]
    f = np.where(wet[:, None], ft + fp, fa)
    return f.sum(axis=0), np.cross(r, f).sum(axis=0)


def bench_kerner_5120() -> dict:
    sph = trimesh.creation.icosphere(4, radius=0.5)
    hulls = HullSet([(sph.vertices, sph.faces)])
    k = KernerForces(hulls, [KernerHydrodynamics()], [60.0])
    pos, rot = np.array([[0.0, 0.0, 0.05]]), np.eye(3)[None]
    verts = hulls.world_vertices(pos, rot).copy()
    rng = np.random.default_rng(0)
    water, eta = rng.normal(size=verts.shape) * 0.1, np.zeros(len(verts))
    v, w, wind, z3 = np.array([[1.5, 0.2, -0.1]]), np.array([[0.05, 0.1, 0.2]]), np.array([[3.0, 0.0, 0.0]]), np.zeros((1, 3))
    kern = best_us(lambda: k.compute(verts, eta, water, pos, v, w, z3, wind, 0.01), 2000)
    with_hs = best_us(lambda: (hulls.compute(verts, eta, pos, 1025.0, 9.81),
                               k.compute(verts, eta, water, pos, v, w, z3, wind, 0.01)), 1000)  # fmt: skip
    tri = verts[sph.faces]
    water_c = water[sph.faces].mean(axis=1)
    base = best_us(lambda: numpy_kerner(tri, water_c, pos[0], v[0], w[0], wind[0]), 200)
    return {"triangles": len(sph.faces), "usvsim_kerner_us": kern, "usvsim_kerner_plus_hydrostatics_us": with_hs,
            "numpy_baseline_us": base, "ratio_numpy_over_usvsim": base / kern,
            "previous_implementation_us": PREVIOUS_US["kerner_5120"],
            "speedup_over_previous": PREVIOUS_US["kerner_5120"] / kern,
            "ratio_seed_over_usvsim_kerner_only": SEED_US["triangle_submersion_5120"] / kern,
            "seed_submersion_only_us": SEED_US["triangle_submersion_5120"],
            "ratio_seed_over_usvsim_full": SEED_US["triangle_submersion_5120"] / with_hs, "target_us": 150.0}  # fmt: skip


def numpy_voxels(centers_body, rot, pos, s, rho=1025.0, g=9.81):
    c = centers_body @ rot.T + pos
    h = c[:, 2]
    dv = np.clip(s * s * (s / 2 - h), 0.0, s**3)
    zc = np.where(h <= -s / 2, c[:, 2], c[:, 2] - 0.5 * (s / 2 + h))
    vol = dv.sum()
    cob = np.array([(dv * c[:, 0]).sum(), (dv * c[:, 1]).sum(), (dv * zc).sum()]) / vol
    f = np.array([0.0, 0.0, rho * g * vol])
    return f, np.cross(cob - pos, f)


def bench_voxels(tmp_cache: Path) -> dict:
    os.environ.setdefault("USVSIM_CACHE", str(tmp_cache))
    sph = trimesh.creation.icosphere(5, radius=0.5)
    grid = voxelize(sph.vertices, sph.faces, 0.05, supersample=1)
    vs = VoxelSet([grid])
    pos, rot = np.array([[0.0, 0.0, 0.1]]), np.eye(3)[None]
    eta = np.zeros(len(grid.centers))

    def step(cut):
        c = vs.world_centers(pos, rot)
        return vs.compute(c, eta, pos, 1025.0, 9.81, cut)

    cut, not_cut = best_us(lambda: step(True), 5000), best_us(lambda: step(False), 5000)
    c = vs.world_centers(pos, rot)
    kernel_only = best_us(lambda: vs.compute(c, eta, pos, 1025.0, 9.81, True), 5000)
    base = best_us(lambda: numpy_voxels(grid.centers, rot[0], pos[0], 0.05), 1000)
    return {"voxels": len(grid.centers), "usvsim_cut_us": cut, "usvsim_not_cut_us": not_cut,
            "usvsim_cut_kernel_only_us": kernel_only, "numpy_baseline_cut_us": base, "ratio_numpy_over_usvsim": base / cut,
            "seed_cut_us": SEED_US["voxel_cut_4154"], "ratio_seed_over_usvsim": SEED_US["voxel_cut_4154"] / cut,
            "target_us": 50.0}  # fmt: skip


def bench_fleet(n_bodies: int = 100) -> dict:
    import numba

    x = np.linspace(-2.0, 2.0, 11)
    hull = loft(x, np.zeros(11), np.full(11, 0.6), np.full(11, 0.4), n_around=18)
    hulls = HullSet([(hull.vertices, hull.faces)] * n_bodies)
    cfgs, masses = [KernerHydrodynamics()] * n_bodies, [300.0] * n_bodies
    serial, parallel = KernerForces(hulls, cfgs, masses), KernerForces(hulls, cfgs, masses, parallel=True)
    rng = np.random.default_rng(0)
    pos = np.column_stack([np.arange(n_bodies) * 10.0, np.zeros(n_bodies), np.full(n_bodies, -0.25)])
    rot = np.tile(np.eye(3), (n_bodies, 1, 1))
    v, w = rng.normal(size=(n_bodies, 3)), rng.normal(size=(n_bodies, 3)) * 0.1
    z3 = np.zeros((n_bodies, 3))
    com = pos + [0.0, 0.0, 0.3]

    def step(k):
        verts = hulls.world_vertices(pos, rot)
        eta = np.zeros(len(verts))
        water = np.zeros_like(verts)
        hulls.compute(verts, eta, com, 1025.0, 9.81)
        k.compute(verts, eta, water, com, v, w, z3, z3, 0.01)

    verts = hulls.world_vertices(pos, rot).copy()
    eta, water = np.zeros(len(verts)), np.zeros_like(verts)
    threads = numba.get_num_threads()
    res = {}
    for label, k, nt in (("1_thread", serial, 1), ("2_threads", parallel, min(2, numba.config.NUMBA_NUM_THREADS))):
        numba.set_num_threads(nt)
        us = best_us(lambda k=k: step(k), 300)
        kern = best_us(lambda k=k: k.compute(verts, eta, water, com, v, w, z3, z3, 0.01), 300)
        res[label] = {"threads": nt, "usvsim_us_per_step": us, "kerner_us_per_step": kern, "kerner_share": kern / us,
                      "real_time_factor_at_100hz": 1e4 / us}  # fmt: skip
    numba.set_num_threads(threads)
    one = res["1_thread"]
    return {"bodies": n_bodies, "triangles_per_hull": len(hull.faces),
            "usvsim_us_per_step": one["usvsim_us_per_step"], "real_time_factor_at_100hz_kernels_only": 1e4 / one["usvsim_us_per_step"],
            **res, "previous_implementation_us_per_step": PREVIOUS_US["fleet_step"],
            "speedup_over_previous_1_thread": PREVIOUS_US["fleet_step"] / one["usvsim_us_per_step"],
            "budget_us_for_5x": 1e6 / 100 / 5}  # 5x real time at 100 Hz; fmt: skip


def main() -> None:
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        result = {"machine": f"{platform.machine()}, {os.cpu_count()} cores", "single_thread": "except fleet 2_threads",
                  "kerner_5120": bench_kerner_5120(), "voxels_4154": bench_voxels(Path(tmp)),
                  "fleet_100x400": bench_fleet()}  # fmt: skip
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    RESULTS.write_text(json.dumps(result, indent=2))
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
