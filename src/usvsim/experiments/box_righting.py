"""`usvsim experiment box-righting`: heeled box, roll moment about G, 0-40° (physics.md §1.10).

Box L = 2, B = 1, D = 1 m, draft T = 0.4 m, KG = 0.3 m, rho = 1000, g = 9.81, heeled by φ about the
centreline point on the waterplane. Compared:
- usvsim's triangle hydrostatics (exact pressure integral, `HullSet`), on 12 and 3072 triangles;
- the wall-sided formula GZ = sin φ (GM + BM tan²φ / 2) (valid until the bottom emerges, 38.7°);
- the exact clipped-polyhedron reference (trimesh's volume and centroid of the submerged part,
  moment = (c_B - G) × ρ g V ẑ), valid at every angle;
- the plain centroid rule (F_i = -ρ g d(c_i) A_i n_i applied at c_i), computed here to show the
  seed's "ghost torque" on coarse meshes.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import trimesh
from trimesh.intersections import slice_faces_plane

from usvsim.hydro.hydrostatics import HullSet

RHO, G = 1000.0, 9.81
L, B, D, T, KG = 2.0, 1.0, 1.0, 0.4, 0.3
ANGLES_DEG = (0.0, 5.0, 10.0, 20.0, 30.0, 40.0)
UNITS = ("heel_deg degrees, a rotation about the box's x axis (FLU, REP 103: positive lowers starboard); every "
         "other figure is the roll moment about G in N m about that axis (negative: righting); wall_sided is "
         "None past 38.7°, where the bottom emerges")  # fmt: skip
TABLE = {5.0: (-74.6452, -25.4271, -74.7136), 10.0: (-152.0493, -55.0967, -151.9819),
         20.0: (-327.8255, -146.3152, -327.8481), 30.0: (-561.3500, -323.3667, -561.4158)}  # fmt: skip


def box_mesh(subdivisions: int = 0) -> trimesh.Trimesh:
    box = trimesh.creation.box((L, B, D))
    box.apply_translation((0.0, 0.0, D / 2 - T))  # keel at z = -T, waterplane at z = 0
    for _ in range(subdivisions):
        box = box.subdivide()
    return box


def rot_x(phi: float) -> np.ndarray:
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def wall_sided(phi: float) -> float:
    bm = B**2 / (12 * T)
    gm = T / 2 + bm - KG
    return -RHO * G * (L * B * T) * np.sin(phi) * (gm + bm * np.tan(phi) ** 2 / 2)


def _submerged(box: trimesh.Trimesh, phi: float):
    verts = box.vertices @ rot_x(phi).T
    v, f = slice_faces_plane(verts, box.faces, np.array([0.0, 0.0, -1.0]), np.zeros(3))[:2]
    return v, f, rot_x(phi) @ np.array([0.0, 0.0, KG - T])


def centroid_rule(box: trimesh.Trimesh, phi: float) -> float:
    v, f, g_pt = _submerged(box, phi)
    tri = v[f]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])  # 2 A n
    c = tri.mean(axis=1)
    force = -RHO * G * (-c[:, 2])[:, None] * 0.5 * cross
    return float(np.cross(c - g_pt, force).sum(axis=0)[0])


def exact_reference(box: trimesh.Trimesh, phi: float) -> float:
    v, f, g_pt = _submerged(box, phi)
    props = trimesh.triangles.mass_properties(v[f], crosses=None, density=1.0, skip_inertia=True)
    vol, cob = props["volume"], props["center_mass"]  # open at z = 0: the cap adds nothing there
    return float(np.cross(cob - g_pt, [0.0, 0.0, RHO * G * vol])[0])


def usvsim_moment(box: trimesh.Trimesh, phi: float) -> float:
    hulls = HullSet([(box.vertices, box.faces)])
    rot = rot_x(phi)[None]
    world = hulls.world_vertices(np.zeros((1, 3)), rot)
    g_pt = (rot[0] @ np.array([0.0, 0.0, KG - T]))[None]
    return float(hulls.compute(world, np.zeros(len(world)), g_pt, RHO, G).torque[0, 0])


def run(out_dir: Path) -> dict:
    coarse, fine = box_mesh(0), box_mesh(4)
    rows = []
    for deg in ANGLES_DEG:
        phi = np.radians(deg)
        rows.append({"heel_deg": deg, "wall_sided": wall_sided(phi) if deg <= 38.0 else None,
                     "exact_clipped": exact_reference(coarse, phi), "usvsim_12": usvsim_moment(coarse, phi),
                     "usvsim_3072": usvsim_moment(fine, phi), "centroid_rule_12": centroid_rule(coarse, phi),
                     "centroid_rule_3072": centroid_rule(fine, phi)})  # fmt: skip
    ok_exact = all(abs(r[k] - r["exact_clipped"]) <= 1e-6 * max(1.0, abs(r["exact_clipped"]))
                   for r in rows for k in ("usvsim_12", "usvsim_3072"))  # fmt: skip
    ok_wall = all(abs(r["usvsim_12"] - r["wall_sided"]) <= 1e-6 * max(1.0, abs(r["wall_sided"]))
                  for r in rows if r["wall_sided"] is not None)  # fmt: skip
    ok_table = all(abs(r["centroid_rule_12"] - TABLE[r["heel_deg"]][1]) < 1e-3 for r in rows if r["heel_deg"] in TABLE)
    worst_centroid = max(abs(r["centroid_rule_12"] / r["wall_sided"] - 1) for r in rows if r["wall_sided"])
    summary = {"usvsim_matches_exact": ok_exact, "usvsim_matches_wall_sided": ok_wall,
               "centroid_rule_reproduces_seed_error": ok_table,
               "centroid_rule_12_worst_rel_err": worst_centroid}  # fmt: skip
    result = {"experiment": "box-righting", "passed": bool(ok_exact and ok_wall and ok_table), "summary": summary,
              "units": UNITS, "rows": rows}  # fmt: skip
    (Path(out_dir) / "box_righting.json").write_text(json.dumps(result, indent=2))
    _plot(Path(out_dir) / "box_righting.png", rows)
    return result


def _plot(path: Path, rows) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    deg = [r["heel_deg"] for r in rows]
    fig, ax = plt.subplots(figsize=(7, 4))
    ws = [(r["heel_deg"], r["wall_sided"]) for r in rows if r["wall_sided"] is not None]
    ax.plot(*zip(*ws), "k-", lw=2, label="wall-sided formula")
    ax.plot(deg, [r["exact_clipped"] for r in rows], "ks", mfc="none", label="exact (clipped polyhedron)")
    ax.plot(deg, [r["usvsim_12"] for r in rows], "o", label="usvsim pressure integral, 12 tris")
    ax.plot(deg, [r["centroid_rule_12"] for r in rows], "v--", label="centroid rule (seed), 12 tris")
    ax.plot(deg, [r["centroid_rule_3072"] for r in rows], "^:", label="centroid rule, 3072 tris")
    ax.set(xlabel="heel φ [deg]", ylabel="roll moment about G [N·m]", title="Heeled box righting moment")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
