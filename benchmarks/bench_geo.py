"""Real places: load time of a 10 km² scene (cold and cached) and the cost of its geometry in a calm step.

The scene (written here as real files, UTM 32N): a square of 3.16 km x 3.16 km = 10 km² around the origin,
land west of a wavy coastline with 5,000 vertices plus two islands, a 1000 x 1000 DEM for the land heights
and a 1000 x 1000 bathymetry GeoTIFF, a quay. Baselines in the same run: the same scenario without its
`geo:` section (construction and calm step of one WAM-V), and bare MuJoCo stepping the geo model.
Figures are medians of REPEATS; the load average is recorded beside them.
Run: python benchmarks/bench_geo.py [--repeats N]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np

HALF_M = 1581.0  # half side: (2 * 1581 m)² = 10.0 km²
ORIGIN = (59.42083, 10.43278)


def write_scene(folder: Path) -> dict:
    import json as js

    import rasterio
    from pyproj import Transformer
    from rasterio.transform import from_origin

    from usvsim.geo.frame import GeoFrame

    frame = GeoFrame(*ORIGIN)
    to_utm = Transformer.from_crs("EPSG:4326", "EPSG:25832", always_xy=True)

    def utm(x, y):
        geo = frame.to_geodetic(np.asarray(x, float), np.asarray(y, float), 0.0)
        return np.column_stack(to_utm.transform(geo[:, 1], geo[:, 0]))

    t = np.linspace(0, 1, 4990)
    coast_y = -2000 + 4000 * t
    coast_x = -600 + 120 * np.sin(coast_y / 90) + 45 * np.sin(coast_y / 17)
    ring = np.vstack([np.column_stack([coast_x, coast_y]), [[-2000, 2000], [-2000, -2000]]])
    islands = [np.column_stack([x0 + r * np.cos(a), y0 + 0.6 * r * np.sin(a)])
               for x0, y0, r, a in ((600, 700, 180, np.linspace(0, 2 * np.pi, 5, endpoint=False)),
                                    (900, -900, 120, np.linspace(0, 2 * np.pi, 5, endpoint=False)))]
    polys = [utm(*ring.T).tolist()] + [utm(*i.T).tolist() for i in islands]
    crs = {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::25832"}}
    (folder / "land.geojson").write_text(js.dumps({"type": "FeatureCollection", "crs": crs, "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [p + [p[0]]]}}
        for p in polys]}))
    quay = utm([-560, -400, -400, -560], [0, 0, 20, 20]).tolist()
    (folder / "quays.geojson").write_text(js.dumps({"type": "FeatureCollection", "crs": crs, "features": [
        {"type": "Feature", "properties": {"height": 1.5}, "geometry": {"type": "Polygon", "coordinates": [quay + [quay[0]]]}}]}))
    e0, n0 = utm([-1700.0], [1700.0])[0]
    cell = 3.4
    cols = np.arange(1000) * cell
    rows = np.arange(1000) * cell
    dem = 5 + 20 * np.abs(np.sin(cols[None, :] / 300) * np.cos(rows[:, None] / 410))
    depth = -(2 + 0.008 * cols[None, :] + 0.0 * rows[:, None])
    for name, values in (("dem.tif", dem), ("depth.tif", depth)):
        with rasterio.open(folder / name, "w", driver="GTiff", height=1000, width=1000, count=1, dtype="float32",
                           crs="EPSG:25832", transform=from_origin(e0, n0, cell, cell)) as ds:
            ds.write(values.astype(np.float32), 1)
    return {"land": folder / "land.geojson", "quays": folder / "quays.geojson", "dem": folder / "dem.tif",
            "depth": folder / "depth.tif"}


def scenario_dict(files: dict, with_geo: bool) -> dict:
    data = {"version": 1, "name": "bench_geo", "world": {"origin": {"latitude_deg": ORIGIN[0], "longitude_deg": ORIGIN[1]}},
            "vessels": [{"name": "wamv", "model": "wamv", "pose": {"position": [200.0, 0.0, 0.0]}}]}
    if with_geo:
        data["geo"] = {"extent_m": HALF_M, "terrain_cell_m": 2.0,
                       "land": {"file": str(files["land"]), "dem": {"file": str(files["dem"])}},
                       "bathymetry": {"file": str(files["depth"])},
                       "structures": [{"file": str(files["quays"])}]}
    return data


def timed(fn) -> float:
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def step_us(sim, steps: int) -> float:
    boat = sim.vessels["wamv"]
    start = time.perf_counter()
    for _ in range(steps):
        boat.command(0.5, 0.1)
        sim.step()
    return 1e6 * (time.perf_counter() - start) / steps


def main(repeats: int) -> dict:
    from usvsim.config.loader import parse_scenario
    from usvsim.geo.resolve import frame_of
    from usvsim.geo.scene import GeoScene
    from usvsim.simulation import Simulation

    tmp = Path(tempfile.mkdtemp())
    os.environ["USVSIM_CACHE"] = str(tmp / "cache")
    files = write_scene(tmp)
    geo_sc = parse_scenario(scenario_dict(files, True), "bench_geo")
    bare_sc = parse_scenario(scenario_dict(files, False), "bench_geo")
    frame = frame_of(geo_sc)
    cold, cached, build_geo, build_bare = [], [], [], []
    for _ in range(repeats):
        shutil.rmtree(tmp / "cache", ignore_errors=True)
        cold.append(timed(lambda: GeoScene.load(geo_sc.geo, frame, tmp)))
        cached.append(timed(lambda: GeoScene.load(geo_sc.geo, frame, tmp)))
        build_geo.append(timed(lambda: Simulation(geo_sc).close()))
        build_bare.append(timed(lambda: Simulation(bare_sc).close()))
    sims = {"geo": Simulation(geo_sc), "bare": Simulation(bare_sc)}
    for sim in sims.values():
        sim.run(1.0)
    steps = 3000
    per_step = {k: [] for k in sims} | {"mujoco_geo_model": []}
    for _ in range(repeats):  # interleaved, so both see the same machine load
        for name, sim in sims.items():
            per_step[name].append(step_us(sim, steps))
        m, d = sims["geo"].model, sims["geo"].data
        per_step["mujoco_geo_model"].append(
            1e6 * timed(lambda m=m, d=d: [mujoco.mj_step(m, d) for _ in range(steps)]) / steps
        )
    med = statistics.median
    result = {
        "scene": {"area_km2": (2 * HALF_M / 1000) ** 2, "coastline_vertices": 5000, "dem": "1000x1000",
                  "bathymetry": "1000x1000", "terrain_cell_m": 2.0,
                  "hfield_tiles": int(sims["geo"].model.nhfield) - 1, "geoms": int(sims["geo"].model.ngeom)},
        "load_cold_s": med(cold), "load_cached_s": med(cached),
        "simulation_build_geo_s": med(build_geo), "simulation_build_bare_s": med(build_bare),
        "calm_step_geo_us": med(per_step["geo"]), "calm_step_bare_us": med(per_step["bare"]),
        "mujoco_step_geo_model_us": med(per_step["mujoco_geo_model"]),
        "step_ratio_geo_over_bare": med(per_step["geo"]) / med(per_step["bare"]),
        "repeats": repeats, "load_average": os.getloadavg(),
    }
    out = Path(__file__).parent / "results" / "geo.json"
    out.write_text(json.dumps(result, indent=2))
    shutil.rmtree(tmp, ignore_errors=True)
    return result


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    print(json.dumps(main(parser.parse_args().repeats), indent=2))
