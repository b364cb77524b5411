"""Pictures and metrics of a navigation run: the map with the true outline, the track, metrics JSON."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from usvsim.autonomy import metrics
from usvsim.autonomy.grid import OccupancyGrid

HULL_LENGTH_M, HULL_BEAM_M = 4.9, 2.4  # WAM-V footprint: the clearance's default


def footprint(vessel) -> tuple[float, float, float, float]:
    """Length and beam (m) of the box around a vessel's hull mesh and its centre (x, y m in base_link, FLU): the
    clearance took the WAM-V's 4.9 m × 2.4 m for every vessel (an Otter is 2.0 m × 1.04 m)."""
    v = np.asarray(vessel.model.hull.vertices)
    lo, hi = v[:, :2].min(axis=0), v[:, :2].max(axis=0)
    return float(hi[0] - lo[0]), float(hi[1] - lo[1]), float(lo[0] + hi[0]) / 2, float(lo[1] + hi[1]) / 2


def summarize(nav, trace, grid: OccupancyGrid, truth_occ: np.ndarray, sim_time_s: float, wall_s: float,
              hull: tuple[float, float, float, float] = (HULL_LENGTH_M, HULL_BEAM_M, 0.0, 0.0)) -> dict:  # fmt: skip
    """The metrics of a run; `hull`: length, beam, centre x, y (m, base_link) of the footprint for the clearance."""
    rows, truth = trace.array(), np.array(trace.truth)
    odo = metrics.ate(rows[:, 0], rows[:, 4:6], truth)
    xte = rows[:, 7][np.isfinite(rows[:, 7]) & (rows[:, 8] > 1.0)]  # while cruising (commanded surge > 1 m/s)
    parts = {k: round(v, 3) for k, v in trace.wall_s.items()}
    return {
        "goals": [list(map(float, g)) for g in nav.goals], "goals_reached": len(nav.reached),
        "goal_times_s": [round(t, 2) for t in nav.reached],
        "final_goal_error_m": _goal_errors(nav, truth),
        "goals_given_up": [{**g, "goal": list(map(float, nav.goals[g["goal"]]))} for g in nav.given_up],
        "collisions": sorted(trace.contacts),
        "map_iou": round(metrics.map_iou(grid, truth_occ, truth[:, 1:3]), 4),  # one-cell tolerance
        "map_iou_strict": round(metrics.map_iou(grid, truth_occ, truth[:, 1:3], tolerance_cells=0), 4),
        **{k: round(v, 4) for k, v in odo.items()},
        "cross_track_rms_m": round(float(np.sqrt(np.mean(xte**2))), 4) if len(xte) else None,
        "cross_track_max_m": round(float(np.abs(xte).max()), 4) if len(xte) else None,
        "min_clearance_m": round(metrics.min_clearance(grid, truth_occ, truth[:, 1:4], *hull), 3),
        "sim_time_s": round(sim_time_s, 2), "wall_time_s": round(wall_s, 2),
        "real_time_factor": round(sim_time_s / wall_s, 3),
        "wall_share": {k: round(v / max(sum(parts.values()), 1e-9), 3) for k, v in parts.items()}, "wall_s": parts,
    }  # fmt: skip


def _goal_errors(nav, truth: np.ndarray) -> list[float]:
    """True distance (m) to each reached goal at the time it was declared reached."""
    out = []
    for goal, t in zip((nav.goals[i] for i in nav.reached_goals), nav.reached):
        k = min(np.searchsorted(truth[:, 0], t), len(truth) - 1)
        out.append(round(float(np.hypot(*(truth[k, 1:3] - goal))), 3))
    return out


def write(out: Path, nav, trace, grid: OccupancyGrid, truth_occ: np.ndarray, summary: dict) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    files = list(grid.save_map(out / "map"))
    rows, truth = trace.array(), np.array(trace.truth)
    x0, y0 = grid.origin_xy
    extent = (x0, x0 + grid.shape[1] * grid.resolution_m, y0, y0 + grid.shape[0] * grid.resolution_m)
    fig, ax = plt.subplots(figsize=(11, 6.8), dpi=110)
    ax.imshow(1.0 - grid.probability(), cmap="gray", origin="lower", extent=extent, vmin=0, vmax=1)
    xs, ys = grid.centres()
    ax.contour(xs, ys, truth_occ.astype(float), levels=[0.5], colors="tab:red", linewidths=0.8)
    for path in trace.paths[-1:]:
        ax.plot(path[:, 0], path[:, 1], ":", color="tab:green", lw=1.2, label="last plan")
    ax.plot(truth[:, 1], truth[:, 2], color="tab:blue", lw=1.2, label="true track")
    ax.plot(rows[:, 4], rows[:, 5], "--", color="tab:orange", lw=1.0, label="LiDAR odometry")
    goals = np.array(nav.goals)
    ax.plot(goals[:, 0], goals[:, 1], "*", ms=12, color="gold", mec="k", label="goals")
    for k, g in enumerate(goals):
        ax.annotate(str(k + 1), g, xytext=(5, 5), textcoords="offset points")
    ax.set(xlabel="x east (m)", ylabel="y north (m)", aspect="equal",
           title=f"map (grey) vs true outline (red): IoU {summary['map_iou']:.2f}; "
                 f"{summary['goals_reached']}/{len(goals)} goals, ATE {summary['ate_rmse_m']:.2f} m")  # fmt: skip
    ax.legend(loc="lower left", fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "map_truth.png")
    plt.close(fig)
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(9, 5), dpi=110, sharex=True)
    a1.plot(rows[:, 0], rows[:, 7], lw=0.8)
    a1.set(ylabel="cross-track (m)", title="cross-track error of the true position on the followed path")
    a2.plot(
        rows[:, 0], np.hypot(rows[:, 1] - rows[:, 4], rows[:, 2] - rows[:, 5]), lw=0.8, color="tab:orange"
    )
    a2.set(xlabel="time (s)", ylabel="odometry error (m)")
    fig.tight_layout()
    fig.savefig(out / "trajectory.png")
    plt.close(fig)
    (out / "metrics.json").write_text(json.dumps(summary, indent=2))
    return [*files, out / "map_truth.png", out / "trajectory.png", out / "metrics.json"]
