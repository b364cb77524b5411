"""Marine radar: a target in the right range bin and spoke and in the ARPA list, clutter statistics of the
configured model, shadowing behind a wall, blind sectors, and sectors/images/tracks read back from an MCAP."""

import math
from types import SimpleNamespace

import numpy as np
import pytest
from readers import read_with_mcap_ros2

from usvsim.io.mcap_recorder import McapRecorder
from usvsim.sensors.radar import clutter
from usvsim.simulation import Simulation

MOUNT_X, MOUNT_Z = 0.0, 3.0
QUIET = {"sea_state": 0, "snr_at_100m_db": -60.0}


def radar_scenario(scenario_of, ships=(), objects=(), **radar):
    cfg = {"type": "radar", "name": "radar", "rpm": 60, "rate_hz": 10, "range_max_m": 1000.0, "spokes": 512,
           "range_bins": 256, "image_size_px": 256,
           "mount": {"position": [MOUNT_X, 0.0, MOUNT_Z]}, "sea_clutter": QUIET, **radar}  # fmt: skip
    return scenario_of({
        "world": {"physics_rate_hz": 50}, "outputs": {"recording": {"clock_rate_hz": 10, "ground_truth_rate_hz": 10}},
        "vessels": [{"name": "wamv", "model": "wamv", "sensors": [cfg]}], "objects": list(objects),
        "traffic": {"ais": {"enabled": False}, "ships": list(ships)},
    })  # fmt: skip


def moored(name, x, y, course=0.0, length=20.0, beam=6.0, mmsi=257000001):
    return {"name": name, "mmsi": mmsi, "length_m": length, "beam_m": beam,
            "motion": {"type": "constant", "position": [x, y], "course_deg": course, "speed_mps": 0.0}}  # fmt: skip


def one_turn(sim, turns=1.0):
    sim.run(turns * 60.0 / sim.sensors["wamv/radar"].cfg.rpm + 0.2)
    return sim.sensors["wamv/radar"]


def test_target_in_its_range_bin_and_spoke_and_in_the_arpa_list(scenario_of, tmp_path):
    # a ship broadside-on 400 m out at 30° to port of the bow (the WAM-V heads east): near side at 397 m
    x, y = 400.0 * math.cos(math.radians(30)), 400.0 * math.sin(math.radians(30))
    sim = Simulation(radar_scenario(scenario_of, [moored("target", x, y, course=120.0)]))
    path = tmp_path / "radar.mcap"
    with McapRecorder(path) as rec:
        sim.subscribe(rec.write)
        radar = one_turn(sim, 3.0)
    pos, _ = radar.pose_world(sim)
    rel = np.array([x, y]) - pos[:2]
    near_face = np.linalg.norm(rel) - 3.0  # beam 6 m, seen side-on
    power = radar.revolution.power
    k, b = np.unravel_index(np.argmax(power), power.shape)
    assert abs(b - int(near_face / radar.bin_m)) <= 1
    angle = math.atan2(rel[1], rel[0]) - sim.vessels["wamv"].rpy[2]
    expected_spoke = round(-angle / (2 * math.pi) * radar.n) % radar.n
    assert min(abs(k - expected_spoke), radar.n - abs(k - expected_spoke)) <= 1
    messages = read_with_mcap_ros2(path)
    tracks = [m for t, _, m in messages if t == "/wamv/radar/tracks"][-1].tracks
    assert len(tracks) == 1
    tr = tracks[0]
    assert tr.range == pytest.approx(np.linalg.norm(rel), abs=3.0 + 2 * radar.bin_m)  # near face and bins
    assert tr.bearing == pytest.approx(math.atan2(rel[0], rel[1]), abs=math.radians(1.0))  # nautical
    assert tr.speed < 0.5
    sectors = [m for t, _, m in messages if t == "/wamv/radar"]
    assert len(sectors) == 32 and sum(len(s.intensities) for s in sectors) == int(3.2 * 512)  # 1 turn/s
    assert len(sectors[0].intensities[0].echoes) == 256
    # marine_sensor_msgs: range_min / range_max are the ranges of a ray's first and last samples (bin centres), so
    # sample j is at range_min + j (range_max - range_min) / (bins - 1): the target's strongest sample at its range
    s = sectors[0]
    assert (s.range_min, s.range_max) == pytest.approx((0.5 * radar.bin_m, 1000.0 - 0.5 * radar.bin_m))
    assert s.range_min + b * (s.range_max - s.range_min) / 255 == pytest.approx((b + 0.5) * radar.bin_m)
    assert abs(s.range_min + b * (s.range_max - s.range_min) / 255 - near_face) <= radar.bin_m
    first = len(sectors[0].intensities)
    assert sectors[1].angle_start == pytest.approx(-first * 2 * math.pi / 512, abs=1e-5)
    assert sectors[1].angle_increment == pytest.approx(-2 * math.pi / 512)  # clockwise
    image = [m for t, _, m in messages if t == "/wamv/radar/image"][-1]
    assert (image.width, image.height, image.encoding) == (256, 256, "mono8")
    sim.close()


def test_bigger_and_broadside_targets_return_more(scenario_of):
    ships = [moored("big", 300, 100, course=90.0, length=40, beam=8), moored("small", 300, -100, course=90.0,
             length=10, beam=3, mmsi=257000002), moored("bow_on", -300, 0, course=90.0, length=40, beam=8, mmsi=257000003)]  # fmt: skip
    radar = one_turn(Simulation(radar_scenario(scenario_of, ships)))
    p = radar.revolution.power

    def total(x, y):  # the whole echo of a target: over ±8° and ±30 m around it
        k = round(-math.atan2(y, x) / (2 * math.pi) * radar.n)
        b = int(math.hypot(x, y) / radar.bin_m)
        rows = np.arange(k - 12, k + 13) % radar.n
        return p[rows, b - 8 : b + 8].sum()

    assert total(300, 100) > 2.5 * total(300, -100)  # size: 40 m x 8 m vs 10 m x 3 m, both side-on
    assert total(300, 100) > 2.0 * total(-300, 0)  # aspect: the same ship broadside (40 m) vs end-on (8 m)


def test_sea_clutter_follows_the_model(scenario_of):
    sim = Simulation(radar_scenario(scenario_of, sea_clutter={"sea_state": 4}))
    radar = one_turn(sim)
    mean_model = 1.0 + clutter.sea_clutter_mean(radar.bin_centres, clutter.SEA_STATE_SNR_DB[4], 3.0)
    p = radar.revolution.power
    for lo, hi in ((20, 40), (60, 100), (150, 250)):  # bins: 40-80 m, 120-200 m, 300-500 m
        measured = p[:, lo:hi].mean(axis=0) / mean_model[lo:hi]
        assert measured.mean() == pytest.approx(1.0, rel=0.12)
    c = 1e4  # K + noise: E[I²]/E[I]² = 2 E[(1 + Cτ)²] / (1 + C)², τ ~ Gamma(ν, 1/ν)
    rng = np.random.default_rng(1)
    sample = clutter.background(rng, (4000, 400), np.full((4000, 400), c), 2.0, np.zeros(400))
    assert sample.mean() == pytest.approx(1 + c, rel=0.03)
    expected = 2 * (1 + 2 * c + c**2 * (1 + 1 / 2.0)) / (1 + c) ** 2
    assert (sample**2).mean() / sample.mean() ** 2 == pytest.approx(expected, rel=0.08)


def test_rain_raises_the_background(scenario_of):
    dry = one_turn(Simulation(radar_scenario(scenario_of))).revolution.power[:, 50:150].mean()
    wet = one_turn(Simulation(radar_scenario(scenario_of, rain_rate_mm_h=8.0))).revolution.power[:, 50:150].mean()
    assert wet > 3.0 * dry


def test_a_wall_shadows_the_target_and_the_sea(scenario_of):
    ship = moored("target", 500.0, 0.0)
    wall = {"type": "wall", "name": "pier", "position": [250.0, 0.0, 0.0], "size": [5.0, 60.0, 20.0]}
    kw = {"sea_clutter": {"sea_state": 5}, "arpa": None}
    open_sea = one_turn(Simulation(radar_scenario(scenario_of, [ship], **kw)))
    shadowed = one_turn(Simulation(radar_scenario(scenario_of, [ship], [wall], **kw)))
    ahead = [-1, 0, 1]  # spokes around the bow (east)
    target_bins = slice(int(490 / open_sea.bin_m), int(500 / open_sea.bin_m) + 2)
    assert open_sea.revolution.power[ahead, target_bins].max() > 100.0
    assert shadowed.revolution.power[ahead, target_bins].max() < 30.0
    beyond = slice(int(300 / open_sea.bin_m), int(450 / open_sea.bin_m))  # sea behind the wall: noise only
    assert shadowed.revolution.power[ahead, beyond].mean() == pytest.approx(1.0, rel=0.3)
    assert open_sea.revolution.power[ahead, beyond].mean() > 1.5


def test_blind_sector_holds_noise_only(scenario_of):
    ship = moored("target", -300.0, 0.0)  # astern
    radar = one_turn(Simulation(radar_scenario(scenario_of, [ship], blind_sectors_deg=[[170.0, 190.0]])))
    astern = radar.n // 2
    assert radar.revolution.power[astern - 3 : astern + 4].max() < 30.0


def test_arpa_tracks_a_moving_target_course_and_speed(scenario_of):
    """A ship steaming north at 6 m/s, 400 m out 30° to port of the bow: after 15 turns the confirmed ARPA track
    has its course (±4°; 2.4° off here) and speed (±0.3 m/s), and its position within a range bin and the beam width (1.8°)."""
    x0, y0 = 400.0 * math.cos(math.radians(30)), 400.0 * math.sin(math.radians(30))
    ship = {"name": "target", "mmsi": 257000001, "length_m": 20.0, "beam_m": 6.0,
            "motion": {"type": "constant", "position": [x0, y0], "course_deg": 0.0, "speed_mps": 6.0}}  # fmt: skip
    sim = Simulation(radar_scenario(scenario_of, [ship]))
    radar = one_turn(sim, 15.0)
    (track,) = radar.revolution.tracker.confirmed()
    own = sim.vessels["wamv"]
    msg = radar.revolution.tracker.message(sim.clock_ns, own.position, sim.world.origin_velocity(own.index)[:2])
    tr = msg.tracks[0]
    assert tr.speed == pytest.approx(6.0, abs=0.3)
    assert math.degrees(math.remainder(tr.course, 2 * math.pi)) == pytest.approx(0.0, abs=4.0)
    truth = np.array([x0, y0 + 6.0 * sim.time])  # the ship's centre now
    rel = truth - own.position[:2]
    assert tr.range == pytest.approx(np.linalg.norm(rel), abs=3.0 + 2 * radar.bin_m)  # its near side, bins
    assert tr.bearing == pytest.approx(math.atan2(rel[0], rel[1]), abs=math.radians(1.8))
    sim.close()


def test_blind_sectors_of_a_whole_turn_and_across_the_stern():
    """[0, 360] made one blind spoke (both ends reduced to 0); a sector of 360° or more is the whole turn. A sector
    whose start is past its end wraps through the bow. Spoke k looks at -k·360/n degrees (clockwise turning)."""
    from types import SimpleNamespace

    from usvsim.sensors.radar.sensor import Radar

    fake = SimpleNamespace(n=360)
    assert Radar._blind_spokes(fake, [(0.0, 360.0)]).all()  # type: ignore[arg-type]
    assert Radar._blind_spokes(fake, [(-10.0, 400.0)]).all()  # type: ignore[arg-type]
    across = Radar._blind_spokes(fake, [(350.0, 10.0)])  # type: ignore[arg-type]
    assert across[0] and across[5] and across[355] and not across[180] and 19 <= across.sum() <= 21
    astern = Radar._blind_spokes(fake, [(170.0, 190.0)])  # type: ignore[arg-type]
    assert astern[180] and not astern[0] and not astern[90] and 19 <= astern.sum() <= 21


def arpa_cfg(spokes=360, bins=100):
    from usvsim.config.sensors import Arpa

    return SimpleNamespace(arpa=Arpa(range_min_m=0.0), range_max_m=1000.0), (spokes, bins)


@pytest.mark.parametrize("centre", [0, 1, 359, 180])
def test_a_plot_across_spoke_0_is_one_plot_with_a_circular_bearing(centre):
    """Spokes are a circle: an echo spanning the last spokes of a turn and the first (spoke 0 is the bow) is one
    plot, its azimuth the circular mean (spoke k looks -k·360/n degrees). 5 spokes × 3 bins of equal power
    around `centre`, 500 m out (bins 49-51 of 10 m): one plot at -centre degrees, 505 m (centroid bin 50 + 0.5)."""
    from usvsim.sensors.radar.arpa import plots

    cfg, (n, bins) = arpa_cfg()
    power = np.ones((n, bins))
    rows = (centre + np.arange(-2, 3)) % n
    power[np.ix_(rows, [49, 50, 51])] = 1000.0
    pose = np.zeros((n, 3))  # antenna at the origin, bow east (ENU yaw 0)
    found = plots(power, pose, np.arange(n) * 0.01, cfg)
    assert len(found) == 1
    (p,) = found
    assert np.hypot(*p.pos) == pytest.approx(505.0, abs=1e-9)
    assert math.degrees(math.atan2(p.pos[1], p.pos[0])) == pytest.approx(math.remainder(-centre, 360.0), abs=1e-9)
    assert p.time_s == pytest.approx(centre * 0.01)  # the centroid spoke's time


def test_plots_that_only_neighbour_across_the_seam_join_and_far_ones_do_not():
    """Detections join when the cells dilated by JOIN_CELLS (2) touch: a gap of up to 4 empty spokes. Pieces
    across the seam with 4 empty spokes between (356-359) are one plot; with 5 (355-359) they are two."""
    from usvsim.sensors.radar.arpa import plots

    cfg, (n, bins) = arpa_cfg()
    power = np.ones((n, bins))
    power[np.ix_([354, 355, 0, 1], [50, 51])] = 1000.0
    assert len(plots(power, np.zeros((n, 3)), np.zeros(n), cfg)) == 1
    power = np.ones((n, bins))
    power[np.ix_([352, 353, 354], [50, 51])] = 1000.0
    power[np.ix_([0, 1, 2], [50, 51])] = 1000.0
    assert len(plots(power, np.zeros((n, 3)), np.zeros(n), cfg)) == 2


def test_a_ship_dead_ahead_is_one_arpa_track(scenario_of):
    """A moored ship 400 m dead ahead (its echo spans the last and the first spokes of a turn) gives one confirmed
    track at bearing 90° true (the WAM-V heads east), not two (found by QA: 0.62° and 359.16°)."""
    sim = Simulation(radar_scenario(scenario_of, [moored("ahead", 400.0, 0.0, course=0.0)]))
    radar = one_turn(sim, 4.0)
    own = sim.vessels["wamv"]
    msg = radar.revolution.tracker.message(sim.clock_ns, own.position, sim.world.origin_velocity(own.index)[:2])
    assert len(msg.tracks) == 1
    (tr,) = msg.tracks
    rel = np.array([400.0, 0.0]) - own.position[:2]
    assert tr.bearing == pytest.approx(math.atan2(rel[0], rel[1]), abs=math.radians(1.0))
    assert tr.range == pytest.approx(np.linalg.norm(rel), abs=10.0 + 2 * radar.bin_m)  # its near end (length 20)
    sim.close()


def test_pieces_of_one_echo_closer_than_join_m_are_one_plot():
    """An echo broken along a ship's length (pieces not touching, even dilated by JOIN_CELLS) is one plot when the
    pieces are closer than arpa.join_m (50 m), at their power-weighted centroid with the strongest piece's time;
    pieces farther apart, or join_m 0, stay separate. 5 m bins, bow east: pieces on spokes 359-1 at 252.5 m and
    282.5 m, 5 empty bins between (equal-ish: a piece 5x stronger would hide the other from the CA-CFAR)."""
    from usvsim.config.sensors import Arpa
    from usvsim.sensors.radar.arpa import plots

    n, bins = 360, 100

    def cfg(join_m):
        return SimpleNamespace(arpa=Arpa(range_min_m=0.0, join_m=join_m), range_max_m=500.0)

    power = np.ones((n, bins))
    power[np.ix_([359, 0, 1], [50])] = 1000.0
    power[np.ix_([359, 0, 1], [56])] = 1000.0
    power[0, 56] = 1200.0  # the stronger piece
    times, pose = np.arange(n) * 0.01, np.zeros((n, 3))
    (one,) = plots(power, pose, times, cfg(50.0))
    assert one.pos == pytest.approx([(3000.0 * 252.5 + 3200.0 * 282.5) / 6200.0, 0.0], abs=1e-6)
    assert one.power == pytest.approx(6200.0) and one.time_s == 0.0
    assert len(plots(power, pose, times, cfg(0.0))) == 2
    assert len(plots(power, pose, times, cfg(25.0))) == 2


def test_a_ship_seen_end_on_is_one_arpa_track(scenario_of):
    """A 30 m ship 800 m out crossing at 5 m/s, seen nearly end-on: its echo breaks into pieces 30-34 m apart
    (found by QA: two confirmed tracks 33 m apart, one coasting at 4.55 m/s); joined, it is one track with the
    ship's course and speed."""
    ship = {"name": "crosser", "mmsi": 257000002, "length_m": 30.0, "beam_m": 8.0,
            "motion": {"type": "constant", "position": [800.0, -200.0], "course_deg": 270.0, "speed_mps": 5.0}}  # fmt: skip
    sim = Simulation(radar_scenario(scenario_of, [ship], rpm=24, spokes=1024, range_bins=512, range_max_m=1500.0,
                                    horizontal_beamwidth_deg=1.8, vertical_beamwidth_deg=22.0, mount={"position": [0.0, 0.0, 2.5]}), seed=0)  # fmt: skip
    radar = sim.sensors["wamv/radar"]
    counts = []
    for _ in range(8):
        sim.run(2.5)
        counts.append(len(radar.revolution.tracker.confirmed()))
    assert counts[-1] == 1 and max(counts) == 1
    (track,) = radar.revolution.tracker.confirmed()
    assert np.hypot(*track.vel) == pytest.approx(5.0, abs=0.3)
    assert math.degrees(math.atan2(track.vel[0], track.vel[1])) % 360.0 == pytest.approx(270.0, abs=3.0)
    sim.close()
