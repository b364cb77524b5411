"""Sphere lowered through flat water: displaced volume vs the analytic cap (the seed thesis's Table 1).

Icospheres of radius R = 0.5 m (80, 320, 1280, 5120 faces) are lowered through still water at
z = 0 (world ENU), the immersion depth d of the nominal sphere's lowest point going from 0 to
2R = 1 m (sphere centre at z = R - d). At each depth the hull hydrostatics kernel's displaced
volume is compared with
- the exact volume of the mesh clipped by the water plane (trimesh's own clipping, independent):
  this isolates the kernel's error, and
- the analytic spherical cap V = π d² (3R - d) / 3: this adds the mesh's discretisation error,
  the quantity the seed reports (max |error| in m³ and as % of the full sphere volume).
The centre of buoyancy's height is compared the same way: with trimesh's centroid of the clipped mesh (within
1e-9 m) and, for 1280 faces, with physics.md §2.3's table (d = 0.25, 0.5, 0.75 m; printed to 5 decimals).
"""

from __future__ import annotations

import json
import pathlib

import numpy as np
import trimesh
from trimesh.intersections import slice_faces_plane
from trimesh.triangles import mass_properties

from usvsim.hydro.hydrostatics import HullSet

RADIUS_M = 0.5
RHO_KG_M3 = 1000.0
G_M_S2 = 9.81
SUBDIVISIONS = (1, 2, 3, 4)  # 80, 320, 1280, 5120 faces
# physics.md §2.3: centre of buoyancy z (m, sphere centre at z = R - d, water at z = 0) of the 1280-face icosphere
PHYSICS_COB_1280 = {0.25: -0.08699, 0.5: -0.18696, 0.75: -0.31202}
UNITS = ("volumes m³, depths m: d is the depth of the sphere's lowest point below still water at z = 0 "
         "(world ENU, z up), centre at z = R - d; errors m³ and % of the sphere's volume")  # fmt: skip
# Seed thesis, triangles with cutting: max abs error (m³), same as % of the sphere, RMS error (m³)
SEED_ERRORS = {
    80: (0.0663, 12.65, 0.0385),
    320: (0.0177, 3.38, 0.0103),
    1280: (0.0045, 0.86, 0.0026),
    5120: (0.0011, 0.22, 0.00066),
}


def cap_volume_m3(depth_m: np.ndarray, radius_m: float = RADIUS_M) -> np.ndarray:
    """Analytic submerged volume of a sphere whose lowest point is depth_m below the surface."""
    d = np.clip(depth_m, 0.0, 2.0 * radius_m)
    return np.pi * d**2 * (3.0 * radius_m - d) / 3.0


def clipped_volume_m3(vertices_enu: np.ndarray, faces: np.ndarray) -> tuple[float, float]:
    """Exact volume (m³) of a closed mesh below z = 0 and its centroid's z (m), by trimesh's clipping (the open cut
    surface suffices: the missing cap lies in z = 0, through the origin, and adds nothing to either)."""
    v, f = slice_faces_plane(vertices_enu, faces, np.array([0.0, 0.0, -1.0]), np.zeros(3))[:2]
    if not len(f):
        return 0.0, float("nan")
    props = mass_properties(v[f], skip_inertia=True)
    return float(props.volume), float(props.center_mass[2])


def sweep(mesh: trimesh.Trimesh, depths_m: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Kernel and clipped-reference displaced volumes (m³) and centres of buoyancy z (m, world ENU; NaN when dry)
    of the mesh lowered through z = 0."""
    hulls = HullSet([(mesh.vertices, mesh.faces)])
    eta = np.zeros(len(mesh.vertices))
    rot = np.eye(3)[None]
    kernel, reference = np.empty(len(depths_m)), np.empty(len(depths_m))
    kernel_cob, reference_cob = np.full(len(depths_m), np.nan), np.empty(len(depths_m))
    for i, depth in enumerate(depths_m):
        pos = np.array([[0.0, 0.0, RADIUS_M - depth]])
        world = hulls.world_vertices(pos, rot)
        res = hulls.compute(world, eta, pos, RHO_KG_M3, G_M_S2)
        kernel[i] = res.volume[0]
        if kernel[i] > 0.0:
            kernel_cob[i] = res.cob[0, 2]
        reference[i], reference_cob[i] = clipped_volume_m3(world, mesh.faces)
    return kernel, reference, kernel_cob, reference_cob


def table_row(n_faces: int, kernel: np.ndarray, reference: np.ndarray, analytic: np.ndarray,
              cob: tuple[np.ndarray, np.ndarray] | None = None) -> dict:
    """Error figures of one mesh next to the seed's; pass = ours <= seed's (as the seed rounds), the kernel's volume
    and (if given: kernel, reference) centre of buoyancy z equal to trimesh's clipped mesh."""
    sphere_m3 = 4.0 / 3.0 * np.pi * RADIUS_M**3
    wet = reference > 0.0
    err = np.abs(kernel - analytic)
    seed_abs, seed_pct, seed_rms = SEED_ERRORS[n_faces]
    row = {
        "faces": n_faces,
        "max_rel_err_vs_clipped": float(np.max(np.abs(kernel - reference)[wet] / reference[wet])),
        "max_abs_err_vs_clipped_m3": float(np.max(np.abs(kernel - reference))),
        "max_abs_err_m3": float(err.max()),
        "max_err_pct_of_sphere": float(100.0 * err.max() / sphere_m3),
        "rms_err_m3": float(np.sqrt(np.mean(err**2))),
        "seed_max_abs_err_m3": seed_abs,
        "seed_max_err_pct_of_sphere": seed_pct,
        "seed_rms_err_m3": seed_rms,
    }
    row["kernel_exact"] = row["max_rel_err_vs_clipped"] <= 1e-9
    if cob is not None:
        wetter = reference > 1e-6  # m³: the centroid of a sliver is ill-conditioned
        row["max_cob_err_vs_clipped_m"] = float(np.max(np.abs(cob[0] - cob[1])[wetter]))
        row["kernel_exact"] = row["kernel_exact"] and row["max_cob_err_vs_clipped_m"] <= 1e-9
    row["pass"] = bool(
        row["kernel_exact"]
        and round(row["max_abs_err_m3"], 4) <= seed_abs
        and round(row["max_err_pct_of_sphere"], 2) <= seed_pct
    )
    return row


def plot(path: pathlib.Path, depths_m: np.ndarray, curves: dict, analytic: np.ndarray) -> None:
    """Volume vs depth for each mesh and the analytic cap; error vs depth."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_v, ax_e) = plt.subplots(1, 2, figsize=(11, 4.2))
    ax_v.plot(depths_m, analytic, "k--", lw=1.5, label="analytic cap")
    for n_faces, c in curves.items():
        volume = np.asarray(c["volume_m3"])
        ax_v.plot(depths_m, volume, lw=1, label=f"{n_faces} faces")
        ax_e.plot(depths_m, volume - analytic, lw=1, label=f"{n_faces} faces")
    ax_v.set(
        xlabel="immersion depth of lowest point d [m]",
        ylabel="displaced volume [m³]",
        title=f"Sphere R = {RADIUS_M} m lowered through flat water",
    )
    ax_e.set(
        xlabel="immersion depth of lowest point d [m]",
        ylabel="computed − analytic [m³]",
        title="Error vs analytic (= mesh discretisation)",
    )
    for ax in (ax_v, ax_e):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def run(out_dir: pathlib.Path, n_depths: int = 401) -> dict:
    """Run the experiment; write sphere.json (table + curves) and sphere.png into out_dir."""
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    depths = np.linspace(0.0, 2.0 * RADIUS_M, n_depths)
    analytic = cap_volume_m3(depths)
    rows, curves = [], {}
    for subdivisions in SUBDIVISIONS:
        mesh = trimesh.creation.icosphere(subdivisions=subdivisions, radius=RADIUS_M)
        kernel, reference, kernel_cob, reference_cob = sweep(mesh, depths)
        rows.append(table_row(len(mesh.faces), kernel, reference, analytic, (kernel_cob, reference_cob)))
        if len(mesh.faces) == 1280:
            cob = sweep(mesh, np.array(list(PHYSICS_COB_1280)))[2]
            cob_table = {f"d={d:g} m": [float(z), ref] for (d, ref), z in zip(PHYSICS_COB_1280.items(), cob)}
        curves[len(mesh.faces)] = {"volume_m3": kernel.tolist(), "clipped_m3": reference.tolist()}
    cob_ok = all(abs(z - ref) <= 1e-5 for z, ref in cob_table.values())  # the table's 5 decimals
    result = {
        "experiment": "sphere",
        "units": UNITS,
        "radius_m": RADIUS_M,
        "table": rows,
        "cob_z_1280_vs_physics_md_m": cob_table,
        "passed": all(r["pass"] for r in rows) and cob_ok,
        "summary": {
            **{f"{r['faces']} faces": f"max error {r['max_abs_err_m3']:.4f} m3 = {r['max_err_pct_of_sphere']:.2f} % "
               f"(seed {r['seed_max_err_pct_of_sphere']} %), kernel vs exact clipped volume "
               f"{r['max_rel_err_vs_clipped']:.1e}, centre of buoyancy {r['max_cob_err_vs_clipped_m']:.1e} m"
               for r in rows},
            "centre of buoyancy z, 1280 faces, vs physics.md 2.3 [m]": cob_table,
        },  # fmt: skip
        "depths_m": depths.tolist(),
        "analytic_m3": analytic.tolist(),
        "curves": {str(k): v for k, v in curves.items()},
    }
    (out_dir / "sphere.json").write_text(json.dumps(result, indent=1))
    plot(out_dir / "sphere.png", depths, curves, analytic)
    return result
