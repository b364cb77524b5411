"""Sensor performance on this machine, each with a baseline measured in the same run.

1. LiDAR: OS1-128 (128 x 2048 = 262,144 rays) on the harbour WAM-V, a physics step between scans; usvsim
   (Embree, 2 threads, full pipeline: rays, cast static + moving bodies, water filter, noise, intensity,
   PointCloud2) vs MuJoCo `mj_multiRay` on the same rays and geoms (visual group); plus the time per scan
   against beam count (16 channels x 250..16000 columns, both casters), the seed's Figure 27, as a PNG.
2. Camera 640x480 RGB + depth + segmentation (two render passes, MuJoCo EGL on llvmpipe) in frames/s, calm
   harbour and sea state 4, against `mujoco.Renderer` (three passes) with its defaults and in its fast
   configuration (shadows, reflections and MSAA off) on the same scene.
3. The seed's demo sensor set on the harbour WAM-V (2D LiDAR 8000 beams 5 Hz, 3D LiDAR 500x16 10 Hz,
   512x512 RGB-D camera 10 Hz, IMU and odometry 50 Hz): real-time factor headless, vs no sensors; and the
   built-in `harbor_sensors` scenario (that set plus GNSS and ground-truth detections) run as a user runs it.

    MUJOCO_GL=egl python benchmarks/bench_sensors.py [--repeats 5] [--seconds 10] [--sections camera demo]
Writes benchmarks/results/sensors.json (sections not run keep their figures) and
benchmarks/results/sensors_beams.png. Timings are medians and bests of `--repeats` runs (camera: 8x as many
frames) after one warm-up, with the median process CPU time (all threads) beside them; the 1-minute load
average is recorded, since the machine is shared.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco
import numpy as np
from pydantic import TypeAdapter

from usvsim import Simulation
from usvsim.config.sensors import Sensor
from usvsim.sensors import SensorSuite

RESULTS = Path(__file__).parent / "results"
LIDAR_MOUNT = {"position": [0.7, 0.0, 1.03]}
CAMERA_MOUNT = {"position": [0.3, 0.0, 1.3], "pitch_deg": 5.0}
DEMO = [
    {"type": "lidar", "name": "scan", "preset": "seed_2d", "rate_hz": 5, "mount": LIDAR_MOUNT},
    {"type": "lidar", "name": "lidar", "preset": "seed_3d", "rate_hz": 10, "mount": LIDAR_MOUNT},
    {"type": "camera", "name": "camera", "width": 512, "height": 512, "horizontal_fov_deg": 60.0, "rate_hz": 10,
     "near_m": 0.01, "far_m": 100.0, "streams": ["rgb", "depth"], "mount": CAMERA_MOUNT},
    {"type": "imu", "name": "imu", "rate_hz": 50, "mount": {"position": [0.0, 0.0, 0.944]}},
    {"type": "odometry", "name": "odometry", "rate_hz": 50},
]  # fmt: skip


def configs(*dicts):
    adapter = TypeAdapter(Sensor)
    return [adapter.validate_python(d) for d in dicts]


CPU_S: dict[str, float] = {}  # median process CPU time (s, all threads) of the last `timed` call per label


def timed(fn, repeats: int, between=None, label: str = "") -> tuple[float, float]:
    """Median and minimum wall time (s) of fn over `repeats` runs after one warm-up; `between()` (untimed)
    runs before each. The median process CPU time (all threads) goes to CPU_S[label]: on the shared machine
    the least disturbed figure."""
    fn()
    times, cpu = [], []
    for _ in range(repeats):
        if between is not None:
            between()
        t, c = time.perf_counter(), time.process_time()
        fn()
        times.append(time.perf_counter() - t)
        cpu.append(time.process_time() - c)
    CPU_S[label] = float(np.median(cpu))
    return float(np.median(times)), float(min(times))


def lidar_sensor(sim, preset: str, **extra):
    suite = SensorSuite(sim, {"wamv": configs({"type": "lidar", "name": "l", "preset": preset, "mount": LIDAR_MOUNT,
                                               **extra})})  # fmt: skip
    return suite, suite["wamv/l"]


def multi_ray(sim, sensor, repeats: int) -> tuple[float, float]:
    """MuJoCo `mj_multiRay` on the sensor's rays (one origin, visual group), nearest geom and distance."""
    origins, dirs, _, _ = sensor._rays(sim)
    n = len(dirs)
    pnt, vec = origins[0].astype(float), np.ascontiguousarray(dirs, float).ravel()
    geomid, dist = np.zeros(n, np.int32), np.zeros(n)
    group = np.array([0, 1, 0, 0, 0, 0], np.uint8)
    mujoco.mj_forward(sim.model, sim.data)
    return timed(lambda: mujoco.mj_multiRay(sim.model, sim.data, pnt, vec, group, 1, -1, geomid, dist, None, n,
                                            sensor.pattern.range_max_m), repeats)  # fmt: skip


def lidar(repeats: int) -> dict:
    """OS1-128 full scan (to the PointCloud2 message) and ranges only, a physics step between scans (bodies
    move); mj_multiRay on the same rays; then the beam sweep, each point with its own baseline."""
    load_start = os.getloadavg()[0]
    sim = Simulation.from_scenario("harbor")
    sim.run(1.0)
    suite, os1 = lidar_sensor(sim, "os1_128")
    n, reps = len(os1.dirs_local), max(15, 3 * repeats)
    med, best = timed(lambda: os1.sample(sim, sim.clock_ns), reps, sim.step, "os1")
    measure_med, measure_best = timed(lambda: os1.measure(sim), reps, sim.step)
    base_med, base_best = multi_ray(sim, os1, max(3, repeats))
    sweep = []
    for columns in (250, 500, 1000, 2000, 4000, 8000, 16000):
        s, sensor = lidar_sensor(sim, "vlp16", columns=columns)
        t, _ = timed(lambda: sensor.sample(sim, sim.clock_ns), reps, sim.step)  # noqa: B023
        b, _ = multi_ray(sim, sensor, max(2, repeats // 2))
        sweep.append({"beams": 16 * columns, "seconds_per_scan": round(t, 5), "mj_multiRay_seconds": round(b, 5)})
        s.close()
    suite.close()
    return {"rays_per_scan": n, "includes": "rays, cast (static + moving bodies), water filter, range limits, noise, "
            "intensity, PointCloud2 message (no CDR)", "repeats": reps, "scan_s_median": round(med, 4),
            "scan_s_min": round(best, 4), "scan_cpu_s_median": round(CPU_S["os1"], 4),
            "mrays_per_s_median": round(n / med / 1e6, 2), "mrays_per_cpu_s_median": round(n / CPU_S["os1"] / 1e6, 2),
            "mrays_per_s_best": round(n / best / 1e6, 2), "ranges_only_s_median": round(measure_med, 4),
            "ranges_only_s_min": round(measure_best, 4), "os1_128_2048_10hz_realtime_factor": round(0.1 / med, 2),
            "os1_128_2048_10hz_realtime_factor_best": round(0.1 / best, 2),
            "baseline_mj_multiRay_s": round(base_med, 4), "baseline_mj_multiRay_s_min": round(base_best, 4),
            "baseline_mrays_per_s": round(n / base_med / 1e6, 2), "speedup_vs_mj_multiRay": round(base_med / med, 1),
            "load_1min_start_end": [round(load_start, 2), round(os.getloadavg()[0], 2)],
            "beam_sweep_vlp16_rows": sweep}  # fmt: skip


def camera(repeats: int) -> dict:
    """The full camera pipeline vs `mujoco.Renderer` on the same machine in the same run."""
    import yaml

    from usvsim.config.loader import resolve

    load_start = load()
    med, best = camera_fps("harbor", repeats * 8)
    cpu_calm = CPU_S["camera"]
    waves = yaml.safe_load(resolve("harbor")[0])
    waves.setdefault("environment", {})["sea"] = {"type": "sea_state", "code": 4}
    wave_med, wave_best = camera_fps(waves, repeats * 8)
    cpu_waves = CPU_S["camera"]
    sim = Simulation.from_scenario("harbor")
    sim.run(0.5)
    base_med, base_best = renderer_fps(sim, repeats * 2, fast=False)
    fast_med, fast_best = renderer_fps(sim, repeats * 4, fast=True)
    r = lambda x: round(x, 1)  # noqa: E731
    return {"fps_median": r(med), "fps_best": r(best), "sea_state_4_fps_median": r(wave_med),
            "sea_state_4_fps_best": r(wave_best), "cpu_ms_per_frame_median": r(cpu_calm * 1e3),
            "sea_state_4_cpu_ms_per_frame_median": r(cpu_waves * 1e3), "includes": "render, water surface (uploaded when it changes: every "
            "frame with waves), readback, depth linearization, sky, segmentation ids, ROS Image messages (no CDR)",
            "baseline_mujoco_Renderer_default_fps_median": r(base_med), "baseline_default_fps_best": r(base_best),
            "baseline_mujoco_Renderer_fast_fps_median": r(fast_med), "baseline_fast_fps_best": r(fast_best),
            "speedup_vs_default_median": round(med / base_med, 2), "speedup_vs_fast_median": round(med / fast_med, 2),
            "load_1min_start_end": [load_start, load()]}  # fmt: skip


CAMERA = {"type": "camera", "name": "cam", "width": 640, "height": 480, "streams": ["rgb", "depth", "segmentation"],
          "mount": CAMERA_MOUNT}  # fmt: skip


def load() -> float:
    return round(os.getloadavg()[0], 2)


def frames_per_s(sim: Simulation, cam, repeats: int) -> tuple[float, float]:
    """(median, best) frames/s of `cam.sample`, one physics step between frames (not timed)."""
    med, best = timed(lambda: cam.sample(sim, sim.clock_ns), repeats, sim.step, "camera")
    return 1 / med, 1 / best


def renderer_fps(sim: Simulation, repeats: int, fast: bool) -> tuple[float, float]:
    """`mujoco.Renderer` RGB, depth and segmentation (three passes) of a view of the WAM-V: defaults, or `fast`
    (shadows and reflections off, no MSAA: the dependency scout's 37.9 fps configuration)."""
    samples = sim.model.vis.quality.offsamples
    sim.model.vis.quality.offsamples = 0 if fast else samples
    renderer = mujoco.Renderer(sim.model, 480, 640)
    sim.model.vis.quality.offsamples = samples
    camera = mujoco.MjvCamera()
    camera.lookat[:], camera.distance, camera.azimuth, camera.elevation = sim.state.pos[0] + [8, 0, 1], 8.0, 180, -5

    def frame():
        renderer.update_scene(sim.data, camera)
        for flag in (mujoco.mjtRndFlag.mjRND_SHADOW, mujoco.mjtRndFlag.mjRND_REFLECTION):
            renderer.scene.flags[flag] = not fast
        renderer.render()
        for mode in ("depth", "segmentation"):
            getattr(renderer, f"enable_{mode}_rendering")()
            renderer.render()
            getattr(renderer, f"disable_{mode}_rendering")()

    med, best = timed(frame, repeats)
    renderer.close()
    return 1 / med, 1 / best


def camera_fps(scenario: str | dict, repeats: int) -> tuple[float, float]:
    """Frames/s of the 640x480 RGB + depth + segmentation camera on the WAM-V of `scenario` (name or dict)."""
    from usvsim.config.loader import load_scenario, parse_scenario

    sim = Simulation(parse_scenario(scenario, "bench") if isinstance(scenario, dict) else load_scenario(scenario))
    sim.run(0.5)
    suite = SensorSuite(sim, {"wamv": configs(CAMERA)})
    try:
        return frames_per_s(sim, suite["wamv/cam"], repeats)
    finally:
        suite.close()


def demo(seconds: float, repeats: int) -> dict:
    """Real-time factor of the harbour with the seed's demo sensors vs none: `repeats` windows of `seconds`."""
    out = {"load_1min_start": load()}
    for label, sensors in (("no_sensors", []), ("demo_sensors", DEMO)):
        sim = Simulation.from_scenario("harbor")
        suite = SensorSuite(sim, {"wamv": configs(*sensors)})
        count = [0]
        sim.run(0.5, on_step=lambda s: suite.on_step(s))  # noqa: B023
        factors, cpu_factors = [], []
        for _ in range(repeats):
            t, c = time.perf_counter(), time.process_time()
            sim.run(seconds, on_step=lambda s: count.__setitem__(0, count[0] + len(suite.on_step(s))))  # noqa: B023
            factors.append(seconds / (time.perf_counter() - t))
            cpu_factors.append(seconds / (time.process_time() - c))
        suite.close()
        out[label] = {"realtime_factor_median": round(float(np.median(factors)), 2),
                      "realtime_factor_best": round(max(factors), 2),
                      "realtime_factor_cpu_median": round(float(np.median(cpu_factors)), 2),
                      "messages": count[0]}  # fmt: skip
    # the built-in `harbor_sensors` scenario as a user runs it: the demo set plus GNSS and ground-truth detections
    # (3D and the camera's 2D boxes), its own obstacles; the sensors step inside `Simulation.run`
    sim = Simulation.from_scenario("harbor_sensors")
    sim.run(0.5)
    factors, cpu_factors = [], []
    for _ in range(repeats):
        t, c = time.perf_counter(), time.process_time()
        sim.run(seconds)
        factors.append(seconds / (time.perf_counter() - t))
        cpu_factors.append(seconds / (time.process_time() - c))
    sim.close()
    out["harbor_sensors_scenario"] = {"realtime_factor_median": round(float(np.median(factors)), 2),
                                      "realtime_factor_best": round(max(factors), 2),
                                      "realtime_factor_cpu_median": round(float(np.median(cpu_factors)), 2)}  # fmt: skip
    out["load_1min_end"] = load()
    return out


def plot(sweep: list[dict], path: Path) -> None:
    """Milliseconds per scan against beams per scan: usvsim (blue) and mj_multiRay on the same rays (grey)."""
    from PIL import Image, ImageDraw

    img = Image.new("RGB", (640, 400), "white")
    d = ImageDraw.Draw(img)
    xs = [s["beams"] for s in sweep]
    series = (("mj_multiRay", "gray", [s["mj_multiRay_seconds"] * 1e3 for s in sweep]),
              ("usvsim (Embree, 2 threads)", "blue", [s["seconds_per_scan"] * 1e3 for s in sweep]))  # fmt: skip
    top = max(max(ys) for _, _, ys in series)
    px = lambda x: 60 + 540 * x / max(xs)  # noqa: E731
    py = lambda y: 360 - 320 * y / top  # noqa: E731
    d.line([(60, 360), (600, 360)], fill="black")
    d.line([(60, 40), (60, 360)], fill="black")
    for k, (label, colour, ys) in enumerate(series):
        d.line([(px(x), py(y)) for x, y in zip(xs, ys)], fill=colour, width=2)
        last_label = -100.0
        for x, y in zip(xs, ys):
            d.ellipse([px(x) - 3, py(y) - 3, px(x) + 3, py(y) + 3], fill=colour)
            if px(x) - last_label > 50:  # labels of crowded points would overlap
                d.text((px(x) - 20, py(y) - 16), f"{y:.1f} ms", fill=colour)
                last_label = px(x)
        d.text((80, 50 + 14 * k), label, fill=colour)
    d.text((230, 375), "beams per scan (16 channels, harbour WAM-V)", fill="black")
    d.text((5, 20), f"ms per scan (max {max(xs)} beams)", fill="black")
    img.save(path)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--sections", nargs="+", choices=["lidar", "camera", "demo"], default=["lidar", "camera", "demo"])
    args = ap.parse_args()
    path = RESULTS / "sensors.json"
    result = json.loads(path.read_text()) if path.is_file() else {}  # sections not run keep their last figures
    result["machine"] = f"{platform.machine()}, {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f} at start"
    if "lidar" in args.sections:
        result["lidar"] = lidar(args.repeats)
        plot(result["lidar"]["beam_sweep_vlp16_rows"], RESULTS / "sensors_beams.png")
    if "camera" in args.sections:
        result["camera_640x480_rgb_depth_seg"] = camera(args.repeats)
    if "demo" in args.sections:
        result["demo_sensor_set_harbor"] = demo(args.seconds, args.repeats)
    RESULTS.mkdir(exist_ok=True)
    path.write_text(json.dumps(result, indent=2) + "\n")
    print(json.dumps({k: result[k] for k in result if k == "machine" or k.split("_")[0] in args.sections}, indent=2))


if __name__ == "__main__":
    main()
