"""A generated corpus of broken and extreme scenario files (`write_corpus(dir)`), for the hardening tests.

Each case is (file name, expectation, content): `error` must be refused with a usvsim error, `ok` must
build, `warn` must build and `validate` must warn. Content is a dict (dumped as YAML), text or bytes.
"""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import trimesh
import yaml

BASE = {
    "version": 1,
    "name": "corpus",
    "world": {"physics_rate_hz": 100, "gravity_mps2": 9.81, "water_density_kgpm3": 1025.0,
              "origin": {"altitude_m": 0.0}},  # fmt: skip
    "environment": {"water_level_m": 0.0},
    "vessels": [{
        "name": "otter", "model": "otter", "mesh_scale": 1.0,
        "pose": {"position": [0.0, 0.0, 0.0], "yaw_deg": 0.0},
        "mass": {"mass_kg": 55.0, "inertia": [10.0, 20.0, 25.0]},
        "sensors": [{"type": "imu", "name": "imu", "rate_hz": 50.0}],
    }],
    "objects": [
        {"type": "dock", "name": "dock", "position": [30.0, 0.0, -1.0], "size": [2.0, 16.0, 3.0]},
        {"type": "buoy", "name": "b1", "position": [-5.0, 5.0, 0.0], "radius_m": 0.3},
        {"type": "pier", "name": "pier", "position": [-20.0, 12.0, 0.8], "length_m": 16.0, "width_m": 3.0,
         "pile_spacing_m": 4.0},
    ],
}  # fmt: skip

FLOAT_PATHS = [
    "world.physics_rate_hz", "world.gravity_mps2", "world.water_density_kgpm3", "world.origin.altitude_m",
    "environment.water_level_m", "vessels.0.pose.position.2", "vessels.0.pose.yaw_deg", "vessels.0.mass.mass_kg",
    "vessels.0.mass.inertia.0", "vessels.0.mesh_scale", "vessels.0.sensors.0.rate_hz", "objects.0.size.1",
    "objects.1.radius_m", "objects.2.pile_spacing_m",
]  # fmt: skip


def _set(data: dict, dotted: str, value) -> dict:
    out = copy.deepcopy(data)
    node, keys = out, [int(k) if k.isdigit() else k for k in dotted.split(".")]
    for key in keys[:-1]:
        node = node[key]
    node[keys[-1]] = value
    return out


def _nonfinite() -> list[tuple[str, str, object]]:
    cases = []
    for path in FLOAT_PATHS:
        for label, value in (("nan", float("nan")), ("inf", float("inf")), ("ninf", float("-inf"))):
            cases.append((f"nonfinite_{path.replace('.', '_')}_{label}", "error", _set(BASE, path, value)))
    return cases


EXTREMES = [  # (name, expectation, dotted path, value)
    ("rate_1hz", "error", "world.physics_rate_hz", 1), ("rate_0", "error", "world.physics_rate_hz", 0),
    ("rate_negative", "error", "world.physics_rate_hz", -100), ("rate_1e9", "error", "world.physics_rate_hz", 1e9),
    ("rate_3hz", "error", "world.physics_rate_hz", 3), ("rate_1khz", "ok", "world.physics_rate_hz", 1000),
    ("rate_10khz", "ok", "world.physics_rate_hz", 10000), ("rate_string", "error", "world.physics_rate_hz", "fast"),
    ("rate_bool", "error", "world.physics_rate_hz", True), ("rate_list", "error", "world.physics_rate_hz", [100]),
    ("gravity_1e9", "error", "world.gravity_mps2", 1e9), ("gravity_0", "error", "world.gravity_mps2", 0),
    ("water_density_tiny", "error", "world.water_density_kgpm3", 1e-9),
    ("water_level_1e6", "error", "environment.water_level_m", 1e6),
    ("mass_1e30", "error", "vessels.0.mass.mass_kg", 1e30), ("mass_0", "error", "vessels.0.mass.mass_kg", 0),
    ("mass_negative", "error", "vessels.0.mass.mass_kg", -5.0), ("mass_tiny", "error", "vessels.0.mass.mass_kg", 1e-30),
    ("inertia_zero", "error", "vessels.0.mass.inertia", [0.0, 0.0, 0.0]),
    ("inertia_negative", "error", "vessels.0.mass.inertia", [-1.0, 20.0, 25.0]),
    ("inertia_two", "error", "vessels.0.mass.inertia", [1.0, 2.0]),
    ("inertia_of_no_rigid_body", "error", "vessels.0.mass.inertia", [1.0, 1.0, 100.0]),  # was MuJoCo's traceback
    ("rate_50hz", "ok", "world.physics_rate_hz", 50),  # was refused for the default 100 Hz /clock
    ("rate_250hz", "ok", "world.physics_rate_hz", 250),
    ("mesh_scale_1e30", "error", "vessels.0.mesh_scale", 1e30), ("mesh_scale_tiny", "error", "vessels.0.mesh_scale", 1e-30),
    ("position_1e9", "error", "vessels.0.pose.position", [1e9, 0.0, 0.0]),
    ("yaw_1e20", "error", "vessels.0.pose.yaw_deg", 1e20),
    ("above_water_100m", "warn", "vessels.0.pose.position", [0.0, 0.0, 100.0]),
    ("below_water_100m", "warn", "vessels.0.pose.position", [0.0, 0.0, -100.0]),
    ("heavier_than_displacement", "warn", "vessels.0.mass.mass_kg", 5000.0),
    ("mesh_scale_of_a_library_hull", "error", "vessels.0.mesh_scale", 2.0),  # was taken and ignored
    ("sea_steeper_than_real_seas", "warn", "environment.sea", {"type": "jonswap", "hs_m": 5.0, "tp_s": 2.0}),
    ("regular_wave_beyond_breaking", "warn", "environment.sea",
     {"type": "regular", "components": [{"amplitude_m": 3.0, "wavelength_m": 10.0}]}),
    ("water_depth_unused_by_fft", "warn", "environment",
     {"water_depth_m": 3.0, "sea": {"type": "sea_state", "code": 3}}),
    ("fft_tiles_hold_little_of_the_sea", "warn", "environment.sea",
     {"type": "sea_state", "code": 4, "realization": {"tile_sizes_m": [1.0]}}),  # 2 % of Hs, silently
    ("fft_tile_sizes_empty", "error", "environment.sea", {"type": "sea_state", "code": 4, "realization": {"tile_sizes_m": []}}),
    ("fft_bands_against_tiles", "error", "environment.sea",
     {"type": "sea_state", "code": 4, "realization": {"tile_sizes_m": [300.0, 60.0], "bands": 3}}),
    ("patch_of_one_point", "error", "vessels.0.water_sampling", {"mode": "patch", "resolution": 1}),
    ("voxels_too_coarse", "warn", "vessels.0.buoyancy", {"type": "voxels", "voxel_size_m": 10.0}),  # none inside
    ("vessel_on_buoy", "warn", "vessels.0.pose.position", [-5.0, 4.6, 0.0]),
    ("vessel_in_dock", "warn", "vessels.0.pose.position", [30.0, 0.0, 0.0]),
    ("dock_size_zero", "error", "objects.0.size", [0.0, 16.0, 3.0]),
    ("dock_size_negative", "error", "objects.0.size", [2.0, -16.0, 3.0]),
    ("dock_size_1e9", "error", "objects.0.size", [1e9, 1.0, 1.0]),
    ("buoy_radius_1e-9", "error", "objects.1.radius_m", 1e-9), ("buoy_radius_1e6", "error", "objects.1.radius_m", 1e6),
    ("pier_length_1e9", "error", "objects.2.length_m", 1e9),
    ("pier_pile_spacing_1e-6", "error", "objects.2.pile_spacing_m", 1e-6),
    ("sensor_rate_1e9", "error", "vessels.0.sensors.0.rate_hz", 1e9),
    ("sensor_rate_7hz", "error", "vessels.0.sensors.0.rate_hz", 7.0),
    ("sensor_latency_half_step", "error", "vessels.0.sensors.0.latency_s", 0.015),  # was rounded to 0.02 s
    ("sensor_latency_1e300", "error", "vessels.0.sensors.0.latency_s", 1e300),  # was an OverflowError
    ("sensor_latency_3_steps", "ok", "vessels.0.sensors.0.latency_s", 0.03),
    ("topic_invalid", "error", "vessels.0.sensors.0.topic", "not a//valid topic!!"),
    ("topic_empty", "error", "vessels.0.sensors.0.topic", ""),
    ("frame_invalid", "error", "vessels.0.sensors.0.frame_id", "a b"),
    ("name_control_chars", "error", "vessels.0.name", "ot\x1bter"),
    ("scenario_name_control_chars", "error", "name", "bad\x07name"),
    ("scenario_name_huge", "error", "name", "x" * 100_000),
    ("model_unknown", "error", "vessels.0.model", "titanic"), ("vessels_empty", "ok", "vessels", []),
    ("vessels_null", "error", "vessels", None), ("objects_not_list", "error", "objects", {"a": 1}),
    ("version_2", "error", "version", 2), ("unknown_key", "error", "world.warp_drive", True),
    ("camera_huge", "error", "vessels.0.sensors",
     [{"type": "camera", "name": "cam", "width": 100_000, "height": 100_000}]),
    ("lidar_1024x100000", "error", "vessels.0.sensors",
     [{"type": "lidar", "name": "lidar", "channels": 1024, "columns": 100_000}]),
    ("lidar_elevations_huge", "error", "vessels.0.sensors",
     [{"type": "lidar", "name": "lidar", "elevations_deg": [0.0] * 5000, "columns": 2048}]),
    ("two_vessels_one_spot", "warn", "vessels",
     [BASE["vessels"][0], {**BASE["vessels"][0], "name": "twin", "sensors": []}]),
    ("dock_on_vessel", "warn", "objects", [{"type": "dock", "name": "dock", "position": [0, 0, 0], "size": [2, 2, 2]}]),
    # QA round: each was accepted (or a traceback) before its fix
    ("fossen_added_mass_two", "error", "vessels.0.hydrodynamics", {"type": "fossen", "added_mass": [1.0, 2.0]}),
    ("fossen_damping_seven", "error", "vessels.0.hydrodynamics", {"type": "fossen", "linear_damping": [1.0] * 7}),
    ("lidar_elevations_empty", "error", "vessels.0.sensors", [{"type": "lidar", "name": "lidar", "elevations_deg": []}]),
    ("lidar_range_min_over_max", "error", "vessels.0.sensors",
     [{"type": "lidar", "name": "lidar", "range_min_m": 50.0, "range_max_m": 10.0}]),
    ("lidar_range_min_over_preset_max", "error", "vessels.0.sensors",
     [{"type": "lidar", "name": "lidar", "preset": "vlp16", "range_min_m": 150.0}]),
    ("lidar_elevation_beyond_90", "error", "vessels.0.sensors",
     [{"type": "lidar", "name": "lidar", "elevations_deg": [-100.0, 0.0, 120.0]}]),
    ("lidar_vertical_fov_reversed", "error", "vessels.0.sensors",
     [{"type": "lidar", "name": "lidar", "vertical_fov_deg": [10.0, -10.0]}]),
    ("odometry_mounted", "error", "vessels.0.sensors",  # was accepted and ignored (base_link reported)
     [{"type": "odometry", "name": "odom", "mount": {"position": [1.0, 0.5, 1.0], "yaw_deg": 90.0}}]),
    ("odometry_default_mount", "ok", "vessels.0.sensors",
     [{"type": "odometry", "name": "odom", "mount": {"position": [0.0, 0.0, 0.0]}}]),
    ("fossen_without_damping", "warn", "vessels.0.hydrodynamics", {"type": "fossen"}),  # ran at 37 m/s, then spun
    ("fossen_otter", "ok", "vessels.0.hydrodynamics", {"type": "fossen", "parameters": "otter"}),
    ("camera_inside_hull", "warn", "vessels.0.sensors",  # sees only the inside of its pontoon (was silent)
     [{"type": "camera", "name": "cam", "mount": {"position": [0.5, 0.4, 0.05]}}]),
    ("camera_on_deck", "ok", "vessels.0.sensors", [{"type": "camera", "name": "cam", "mount": {"position": [0.0, 0.0, 0.3]}}]),
    ("camera_near_beyond_far", "error", "vessels.0.sensors",
     [{"type": "camera", "name": "cam", "near_m": 10.0, "far_m": 1.0}]),
    ("two_sensors_one_topic", "error", "vessels.0.sensors",
     [{"type": "imu", "name": "imu", "topic": "/x"}, {"type": "gnss", "name": "gps", "topic": "/x"}]),
    ("latlon_beyond_100km", "error", "vessels.0.pose", {"latlon": [0.0, 0.0]}),
    ("heading_and_yaw", "error", "vessels.0.pose", {"heading_deg": 90.0, "yaw_deg": 10.0}),
    ("heading_only", "ok", "vessels.0.pose", {"heading_deg": 90.0}),
    # a sensor frame that breaks /tf_static's tree (self transform, a cycle, a second parent) was accepted
    ("sensor_frame_base_link", "error", "vessels.0.sensors", [{"type": "imu", "name": "imu", "frame_id": "otter/base_link"}]),
    ("sensor_frame_world", "error", "vessels.0.sensors", [{"type": "imu", "name": "imu", "frame_id": "world"}]),
    ("two_sensors_one_frame", "error", "vessels.0.sensors",
     [{"type": "imu", "name": "imu", "frame_id": "x"}, {"type": "gnss", "name": "gps", "frame_id": "x"}]),
    ("sensor_frame_own", "ok", "vessels.0.sensors", [{"type": "imu", "name": "imu", "frame_id": "otter/imu_link"}]),
    # a controller on a vessel without thrusters ran and commanded nothing
    ("controller_without_thrusters", "error", "vessels.0",
     {**BASE["vessels"][0], "thrusters": [], "controller": {"type": "velocity"}}),
    ("controller_with_thrusters", "ok", "vessels.0", {**BASE["vessels"][0], "controller": {"type": "velocity"}}),
    # a voxel grid too fine for the hull was a MemoryError traceback (TiB) or a run into the OOM killer
    ("voxels_too_fine", "error", "vessels.0.buoyancy", {"type": "voxels", "voxel_size_m": 0.0001}),
    ("voxels_fine_enough", "ok", "vessels.0.buoyancy", {"type": "voxels", "voxel_size_m": 0.1}),
    # a topic of the simulation's own, or of another part, as a sensor's or traffic's topic (was a ValueError
    # from the recorder mid-run); traffic topics that are no ROS names (were accepted)
    ("sensor_on_clock", "error", "vessels.0.sensors", [{"type": "imu", "name": "imu", "topic": "/clock"}]),
    ("sensor_on_ground_truth", "error", "vessels.0.sensors",
     [{"type": "imu", "name": "imu", "topic": "/otter/ground_truth/odometry"}]),
    ("sensor_on_cmd_vel", "error", "vessels.0.sensors", [{"type": "ground_truth", "name": "cmd_vel"}]),
    ("ais_topic_empty", "error", "traffic", {"ais": {"topic": ""}}),
    ("ais_topic_on_awareness", "error", "traffic", {"awareness": {"topic": "/ais"}}),
    ("awareness_on_tf", "error", "traffic", {"awareness": {"topic": "/tf"}}),
    ("ais_topic_own", "ok", "traffic", {"ais": {"topic": "/my/ais"}}),
    # FFT seas whose tiles cannot cascade were a ValueError traceback from ocean/fft.py
    ("sea_fft_32_three_bands", "error", "environment.sea",
     {"type": "sea_state", "code": 3, "realization": {"method": "fft", "resolution": 32}}),
    ("sea_fft_32_one_band", "warn", "environment.sea",  # 32 cells hold 80 % of Hs
     {"type": "sea_state", "code": 3, "realization": {"method": "fft", "resolution": 32, "bands": 1}}),
    ("sea_fft_tiles_increasing", "error", "environment.sea",
     {"type": "sea_state", "code": 3, "realization": {"method": "fft", "resolution": 64, "tile_sizes_m": [10, 20]}}),
    ("sea_phillips_128", "error", "environment.sea", {"type": "phillips", "resolution": 128}),
    ("sea_phillips_5000m_1024", "ok", "environment.sea",
     {"type": "phillips", "repetition_size_m": 5000, "resolution": 1024}),
]  # fmt: skip


def _bomb(levels: int) -> str:
    lines = ['a0: &a0 ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    for i in range(1, levels):
        p = f"*a{i - 1}"
        lines.append(f"a{i}: &a{i} [{', '.join([p] * 9)}]")
    return "version: 1\n" + "\n".join(lines) + f"\nname: *a{levels - 1}\n"


def _text_cases() -> list[tuple[str, str, object]]:
    deep_list = "version: 1\nname: " + "[" * 5000 + "]" * 5000 + "\n"
    deep_map = "version: 1\nworld: " + "{a: " * 3000 + "1" + "}" * 3000 + "\n"
    return [
        ("alias_bomb_6", "error", _bomb(6)), ("alias_bomb_9", "error", _bomb(9)),
        ("deep_list", "error", deep_list), ("deep_map", "error", deep_map),
        ("binary", "error", bytes(range(256)) * 4), ("png_header", "error", b"\x89PNG\r\n\x1a\n" + b"\0" * 64),
        ("latin1", "error", "version: 1\nname: caf\xe9\n".encode("latin-1")),
        ("utf16", "error", "version: 1\n".encode("utf-16")), ("utf8_bom", "ok", b"\xef\xbb\xbf" + yaml.safe_dump(BASE).encode()),
        ("empty", "error", ""), ("only_comment", "error", "# nothing here\n"), ("scalar", "error", "42\n"),
        ("list_top", "error", "- version: 1\n"), ("tabs", "error", "version: 1\n\tname: x\n"),
        ("unclosed_bracket", "error", "version: 1\nvessels: [\n"), ("python_tag", "error", "version: 1\nname: !!python/object:os.system ls\n"),
        ("custom_tag", "error", "version: 1\nname: !secret x\n"), ("int_key", "error", "version: 1\n1: 2\n"),
        ("huge_int", "error", "version: 1\nworld: {physics_rate_hz: " + "9" * 4000 + "}\n"),
        ("huge_key", "error", "version: 1\n" + "k" * 100_000 + ": 1\n"),
        ("many_aliases", "error", "version: 1\nx: &x 1\nlist: [" + ", ".join(["*x"] * 1000) + "]\n"),
        ("too_big", "error", "version: 1\n" + "# padding\n" * 500_000),
        ("duplicate_vessel_names", "error", yaml.safe_dump(_set(BASE, "objects.1.name", "otter"))),
        ("multi_document", "error", "version: 1\n---\nversion: 1\n"),
        ("duplicate_key", "error", yaml.safe_dump(BASE) + "vessels: []\n"),  # the second silently replaced the first
        ("duplicate_nested_key", "error", "version: 1\nworld: {physics_rate_hz: 100, physics_rate_hz: 50}\n"),
        ("merge_key_override", "ok", "version: 1\nvessels:\n  - &v {name: otter, model: otter}\n"
         "  - {<<: *v, name: twin, pose: {position: [0, 20, 0]}}\n"),  # keys over a merge are no duplicates
    ]  # fmt: skip


def _mesh_cases(directory: Path) -> list[tuple[str, str, object]]:
    box = trimesh.creation.box(extents=(2.0, 1.0, 1.0))
    trimesh.Trimesh(box.vertices, np.asarray(box.faces)[:-1], process=False).export(directory / "open.stl")
    (directory / "garbage.stl").write_bytes(b"solid x\nthis is not a mesh\n")
    (directory / "empty.obj").write_text("")
    big = trimesh.creation.icosphere(subdivisions=7, radius=1.0)  # 328 k faces: over the face limit
    big.export(directory / "huge.stl")
    trimesh.creation.torus(3.0, 1.0, major_sections=200, minor_sections=60).export(directory / "torus.stl")
    obstacle = {"type": "mesh", "name": "rock", "position": [10.0, 10.0, 0.0]}
    custom = {"name": "hull", "model": "custom", "pose": {"position": [0.0, -20.0, 0.0]}, "mass": {"mass_kg": 100.0}}
    return [
        ("mesh_open_obstacle", "error", _set(BASE, "objects", [{**obstacle, "file": "open.stl"}])),
        ("mesh_garbage_obstacle", "error", _set(BASE, "objects", [{**obstacle, "file": "garbage.stl"}])),
        ("mesh_empty_obstacle", "error", _set(BASE, "objects", [{**obstacle, "file": "empty.obj"}])),
        ("mesh_missing_obstacle", "error", _set(BASE, "objects", [{**obstacle, "file": "nope.stl"}])),
        ("mesh_huge_obstacle", "error", _set(BASE, "objects", [{**obstacle, "file": "huge.stl"}])),
        ("mesh_big_nonconvex_obstacle", "error", _set(BASE, "objects", [{**obstacle, "file": "torus.stl"}])),
        ("mesh_open_hull", "error", _set(BASE, "vessels", [{**custom, "hull_mesh": "open.stl"}])),
        ("mesh_huge_hull", "error", _set(BASE, "vessels", [{**custom, "hull_mesh": "huge.stl"}])),
        ("mesh_hull_is_directory", "error", _set(BASE, "vessels", [{**custom, "hull_mesh": "."}])),
    ]


def cases(directory: Path) -> list[tuple[str, str, object]]:
    extremes = [(name, expect, _set(BASE, path, value)) for name, expect, path, value in EXTREMES]
    return [("base", "ok", BASE), *_nonfinite(), *extremes, *_text_cases(), *_mesh_cases(directory)]


def write_corpus(directory: Path) -> list[tuple[Path, str]]:
    """Write every case as `<name>.yaml` under `directory`; returns (path, expectation) pairs."""
    directory.mkdir(parents=True, exist_ok=True)
    out = []
    for name, expect, content in cases(directory):
        path = directory / f"{name}.yaml"
        if isinstance(content, bytes):
            path.write_bytes(content)
        elif isinstance(content, str):
            path.write_text(content)
        else:
            path.write_text(yaml.safe_dump(content, allow_unicode=True, width=10_000))
        out.append((path, expect))
    return out
