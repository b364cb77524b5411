"""Wakes: tracks sampled on simulated time, foam behind a moving hull in RGB only, none behind one at rest."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("moderngl")

from usvsim.rendering.gallery import load, scenario_dict


def _run(wake_s: float, thrust: float, seed: int = 0):
    raw = scenario_dict(1, {"water": {"wake_s": wake_s}}, 160, 120)
    raw["vessels"][0]["pose"] = {"position": [0.0, -30.0, 0.0], "yaw_deg": 180.0}
    raw["vessels"][0]["sensors"][0]["mount"] = {
        "position": [-1.0, 0.0, 3.0],
        "yaw_deg": 180.0,
        "pitch_deg": 25.0,
    }
    sim = load(raw, seed)
    boat = sim.vessels["wamv"]
    for _ in range(600):
        boat.command(thrust, 0.0)
        sim.step()
    images = sim.sensors["wamv/camera"].render(sim.world)  # as the sensor suite samples it: with the World
    samples = len(sim.wakes.samples)
    ribbons = sim.wakes.ribbons(sim.time, wake_s)
    sim.close()
    return images, samples, ribbons


def test_wake_behind_a_moving_hull_changes_rgb_only():
    wake, samples, ribbons = _run(30.0, 1.0)
    none, _, _ = _run(0.0, 1.0)
    assert samples == 24  # 6 s at one sample per 0.25 s of simulated time
    assert len(ribbons) and ribbons[:, 3].max() <= 6.0  # ages within the track
    assert np.array_equal(wake["segmentation"], none["segmentation"])
    assert np.array_equal(wake["depth"], none["depth"], equal_nan=True)
    brighter = wake["rgb"].astype(int).sum(axis=2) - none["rgb"].astype(int).sum(axis=2)
    assert (brighter > 60).mean() > 0.02  # foam on the water astern
    again, _, _ = _run(30.0, 1.0)
    assert np.array_equal(again["rgb"], wake["rgb"])  # same seed, same bytes


def test_no_wake_at_rest():
    _, samples, ribbons = _run(30.0, 0.0)
    assert samples == 24 and len(ribbons) == 0


def test_track_samples_are_each_hulls_stern_heading_and_speed():
    """A sample row per hull: the stern point, heading and speed over ground of the body frame's origin
    (World.origin_velocity), for vessels and kinematic traffic ships alike."""
    import math

    from usvsim.rendering.lights import kinematic_ships
    from usvsim.simulation import Simulation

    sim = Simulation.from_scenario("imazu_05")
    boat = next(iter(sim.vessels.values()))
    for _ in range(3 * sim.wakes.every):
        boat.command(0.8, 0.3)
        sim.step()
    row, world = sim.wakes.samples[-1], sim.world
    assert len(sim.wakes.samples) == 3 and row.shape == (len(sim.wakes.half_beams), 5)
    for k, (vessel, stern, _) in enumerate(sim.wakes.vessels):
        fwd = world.state.rot[vessel.index][:, 0]
        vel = world.origin_velocity(vessel.index)
        expected = [*(world.state.pos[vessel.index] + stern * fwd)[:2], math.atan2(fwd[1], fwd[0]),
                    math.hypot(vel[0], vel[1]), sim.time]  # fmt: skip
        assert row[k] == pytest.approx(expected, rel=1e-12, abs=1e-12)
    _, pos, vel, yaw = kinematic_ships(world)
    assert sim.wakes.ships, "imazu_05 has kinematic targets"
    for j, (stern, _) in enumerate(sim.wakes.ships):
        k = len(sim.wakes.vessels) + j
        expected = [pos[j, 0] + stern * math.cos(yaw[j]), pos[j, 1] + stern * math.sin(yaw[j]), yaw[j],
                    math.hypot(*vel[j]), sim.time]  # fmt: skip
        assert row[k] == pytest.approx(expected, rel=1e-12, abs=1e-12)
    sim.close()


def test_water_without_the_wake_texture_outside_its_region_gives_the_same_bytes(monkeypatch):
    """The water's quads that cannot reach the wakes' texture region are drawn with the program compiled without
    it (MarinePass._marks_runs): the image is byte for byte the one drawn with the full program everywhere, and
    the split leaves part of the grid (here, a camera looking astern along the wake: the far water) to the cheaper
    program."""
    from usvsim.rendering.marine import MarinePass

    runs_seen = []
    split = MarinePass._marks_runs

    def recorded(self, *args):
        runs = split(self, *args)
        runs_seen.append((runs, self._rows, self._columns[args[0]]))
        return runs

    monkeypatch.setattr(MarinePass, "_marks_runs", recorded)
    wake, _, _ = _run(30.0, 1.0)
    runs, (first, count), columns = runs_seen[-1]
    start, stop = first * (columns - 1), (first + count - 1) * (columns - 1)  # the quads drawn
    marked = int(np.diff(np.clip(runs, start, stop), axis=1).sum())
    assert 0 < marked < stop - start
    monkeypatch.setattr(MarinePass, "_marks_runs", lambda self, *args: np.array([[0, 10**9]]))
    whole, _, _ = _run(30.0, 1.0)
    assert np.array_equal(wake["rgb"], whole["rgb"])
    none, _, _ = _run(0.0, 1.0)
    assert not np.array_equal(wake["rgb"], none["rgb"])  # the wake is in the picture the split drew


def test_waterline_taps_from_a_uniform_give_the_same_bytes_as_a_fixed_count(monkeypatch):
    """WATER_FS loops over its waterline depth taps up to a uniform (u_pierce_taps), which llvmpipe does not unroll
    and so can leave early: the picture is the one the fixed count of 8 draws, and the taps do show in it."""
    from usvsim.rendering import marine, shaders

    uniform, _, _ = _run(30.0, 1.0)
    for name in ("WATER_FS", "WATER_MARKS_FS"):
        source = getattr(shaders, name)
        assert "i < u_pierce_taps;" in source
        monkeypatch.setattr(shaders, name, source.replace("i < u_pierce_taps;", f"i < {marine.PIERCE_TAPS};"))
    fixed, _, _ = _run(30.0, 1.0)
    assert np.array_equal(uniform["rgb"], fixed["rgb"])
    monkeypatch.setattr(marine, "PIERCE_TAPS", 0)  # no taps: no geom pierces, no waterline foam
    for name in ("WATER_FS", "WATER_MARKS_FS"):
        monkeypatch.setattr(shaders, name, getattr(shaders, name).replace(" i < 8;", " i < u_pierce_taps;"))
    none, _, _ = _run(30.0, 1.0)
    assert not np.array_equal(uniform["rgb"], none["rgb"])


def _tracks(speeds: list[float], seconds: float = 30.0):
    """WakeTracks of two hulls 40 m apart sailing east at `speeds` (m/s), sampled every 0.25 s for `seconds`."""
    from usvsim.rendering.wakes import SAMPLE_S, WakeTracks

    tracks = WakeTracks.__new__(WakeTracks)
    tracks.half_beams = [1.2, 0.5]
    tracks.reset()
    for i in range(int(seconds / SAMPLE_S) + 1):
        t = i * SAMPLE_S
        tracks.samples.append(np.array([[v * t, 40.0 * k, 0.0, v, t] for k, v in enumerate(speeds)]))
    return tracks, seconds


@pytest.mark.parametrize("speeds, faded", [((0.36, 0.5), True), ((2.5, 0.32), True), ((1.2, 0.0), False)])
def test_wake_cells_hold_every_texel_the_foam_leaves(speeds, faded):
    """WakePass.occupied marks the cells where a triangle can leave foam in the 8-bit texture (wakes.foam_bound, an
    upper bound of the shader's value): every texel above 0, and its bilinear neighbours, lie in marked cells. A slow
    hull's old track fades out of them, so the water draws its quads without the wake code."""
    from usvsim.rendering.gl import attach_current
    from usvsim.rendering.wakes import CELLS, TEXELS, WakePass, foam_bound
    from usvsim.sensors.camera.render import gl_context

    tracks, now = _tracks(list(speeds))
    tris = tracks.ribbons(now, 30.0)
    gl = gl_context(64, 64)
    gl.make_current()
    try:
        ctx = attach_current()
        wakes = WakePass(ctx)
        assert wakes.draw(tris)
        foam = np.frombuffer(wakes.texture.read(), np.uint8).reshape(TEXELS, TEXELS, 4)[..., 0]
        wakes.release()
    finally:
        gl.free()
    assert foam.any()
    rows, cols = np.nonzero(foam)
    for dy in (-1, 0, 1):  # the texel and its bilinear neighbours
        for dx in (-1, 0, 1):
            r, c = np.clip(rows + dy, 0, TEXELS - 1), np.clip(cols + dx, 0, TEXELS - 1)
            assert wakes.occupied[r * CELLS // TEXELS, c * CELLS // TEXELS].all()
    kept = int((foam_bound(tris) >= 0.25 / 255).sum())
    assert 0 < kept and (kept < len(tris) // 3) == faded  # a slow hull's old track is left out (1.2 m/s: 30 s kept)
    assert wakes.occupied.sum() < CELLS * CELLS


def test_slow_hull_water_drawn_with_fewer_wake_quads_gives_the_same_bytes(monkeypatch):
    """A hull under 1 m/s leaves foam only near its stern (the rest of its track rounds to 0 in the texture): the
    water draws the wake code over fewer quads than the track's ribbons cover, and the picture is byte for byte the
    one drawn with the wake code everywhere."""
    from usvsim.rendering.marine import MarinePass
    from usvsim.rendering.wakes import CLEAR, foam_bound

    seen = []
    split = MarinePass._marks_runs

    def recorded(self, *args):
        runs = split(self, *args)
        seen.append(int(np.diff(runs, axis=1).sum()))
        return runs

    monkeypatch.setattr(MarinePass, "_marks_runs", recorded)
    slow, _, ribbons = _run(30.0, 0.3)
    speed = ribbons[:, 4].max()
    assert 0.3 < speed < 1.0, speed  # slow, with a track
    bound = foam_bound(ribbons)
    assert 0 < (bound >= CLEAR).sum() < len(bound)  # its older part leaves no foam
    from usvsim.rendering import wakes

    monkeypatch.setattr(wakes, "foam_bound", lambda tris: np.ones(len(tris) // 3))  # every triangle's cells
    loose, _, _ = _run(30.0, 0.3)
    assert seen[0] < seen[-1]  # fewer quads drawn with the wake code (here none: its foam is out of view)
    assert np.array_equal(slow["rgb"], loose["rgb"])
    monkeypatch.setattr(MarinePass, "_marks_runs", lambda self, *args: np.array([[0, 10**9]]))
    whole, _, _ = _run(30.0, 0.3)
    assert np.array_equal(slow["rgb"], whole["rgb"])


def test_a_teleport_cuts_the_track():
    """A teleported hull did not sail from where it was: its track restarts at the new place, the wake it left
    before stays, and no ribbon joins the two (one did: a streak of foam 40 m across open water)."""
    from usvsim.simulation import Simulation

    sim = Simulation.from_scenario("harbor")
    boat = sim.vessels["wamv"]
    boat.command(1.0)
    sim.run(6.0)
    x, y, _ = boat.position
    boat.teleport((x, y + 40.0, 0.0, 0.0, 0.0, 0.0), twist=(2.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    sim.run(3.0)
    tris = sim.wakes.ribbons(sim.time, 30.0).reshape(-1, 3, 6)
    a, b = tris[:, [0, 1, 2]], tris[:, [1, 2, 0]]
    along = a[..., 2] == b[..., 2]  # edges along one side of a ribbon: samples 0.25 s apart
    assert np.linalg.norm(a[..., :2] - b[..., :2], axis=2)[along].max() < 5.0
    north = tris[..., 1].mean(axis=1) > y + 20.0
    assert north.any() and (~north).any()  # the new track and the old one
    sim.reset()
    assert not any(sim.wakes.cuts) and len(sim.wakes.ribbons(0.0, 30.0)) == 0
    sim.close()
