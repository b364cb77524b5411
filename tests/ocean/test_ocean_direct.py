"""Direct sum of components: §4.6 worked example, Gerstner sign convention, Airy kinematics, VRX wavefield."""

import math

import numpy as np
import pytest

from usvsim.ocean import spectra
from usvsim.ocean.components import from_arrays, random_sea, vrx_pms_components
from usvsim.ocean.direct import DirectWaveField


@pytest.fixture
def worked():
    """physics.md §4.6: (A, λ, dir, φ, Q) = (0.5, 20, 0°, 0, 0.8), (0.25, 9, 30°, 1, 0.8), (0.1, 4, -45°, 2, 0.8)."""
    comps = from_arrays(
        [0.5, 0.25, 0.1],
        2 * np.pi / np.array([20.0, 9.0, 4.0]),
        np.radians([0, 30, -45]),
        [0.0, 1.0, 2.0],
        0.8,
    )
    return DirectWaveField(comps)


def test_worked_example_component_data(worked):
    c = worked.components
    np.testing.assert_allclose(c.k, [0.314159, 0.698132, 1.570796], atol=1e-6)
    np.testing.assert_allclose(c.omega, [1.755535, 2.616997, 3.925495], atol=1e-6)
    assert c.fold_margin == pytest.approx(0.390954, abs=1e-6)


@pytest.mark.parametrize(
    "t, naive, x0, true_height",
    [(0.0, -0.003197, (3.254203, 1.036178), -0.009550), (2.0, -0.628397, (2.717837, 0.888681), -0.683306)],
)
def test_worked_example_4_6(worked, t, naive, x0, true_height):
    px, py = np.array([3.0]), np.array([1.0])
    lx, ly, z, iters = worked.surface_labels(px, py, t, return_iterations=True)
    assert (lx[0], ly[0]) == pytest.approx(x0, abs=1e-6)
    assert z[0] == pytest.approx(true_height, abs=1e-6)  # acceptance: within 1 mm
    assert iters[0] <= 3
    assert worked.naive_elevation(px, py, t)[0] == pytest.approx(naive, abs=1e-6)
    # the label is displaced exactly onto the query point
    np.testing.assert_allclose(worked.displaced_surface(lx, ly, t)[0], [3.0, 1.0, z[0]], atol=1e-9)


def test_gerstner_sharp_crests_flat_troughs():
    """§4.4/§4.5 sign convention: with Q > 0 the crest is narrower than the trough."""
    sea = DirectWaveField(from_arrays(1.0, 2 * math.pi / 20.0, 0.0, 0.0, 0.9))
    x = np.linspace(-10.0, 10.0, 20001)  # one wavelength centred on the crest at x = 0
    above = sea.elevation(x, np.zeros_like(x), 0.0) > 0
    crest_width = above.sum() * (x[1] - x[0])
    assert crest_width < 20.0 - crest_width
    assert sea.elevation(np.array([0.0]), np.array([0.0]), 0.0)[0] == pytest.approx(1.0)


def test_airy_kinematics_closed_form():
    a, k, phase = 0.4, 2 * math.pi / 30.0, 0.3
    sea = DirectWaveField(from_arrays(a, k, math.radians(60), phase, 0.0))
    w = math.sqrt(spectra.G * k)
    x, y, z, t = np.array([2.0]), np.array([-1.0]), np.array([-1.5]), 1.7
    theta = k * (x[0] * math.cos(math.radians(60)) + y[0] * math.sin(math.radians(60))) - w * t + phase
    eta = a * math.cos(theta)
    decay = math.exp(k * (z[0] - eta))  # Wheeler stretching in deep water
    d = np.array([math.cos(math.radians(60)), math.sin(math.radians(60))])
    vel, acc = sea.kinematics(x, y, z, t)
    np.testing.assert_allclose(vel[0, :2], a * w * decay * math.cos(theta) * d, atol=1e-12)
    assert vel[0, 2] == pytest.approx(a * w * decay * math.sin(theta), abs=1e-12)
    np.testing.assert_allclose(acc[0, :2], a * w * w * decay * math.sin(theta) * d, atol=1e-12)
    assert acc[0, 2] == pytest.approx(-a * w * w * decay * math.cos(theta), abs=1e-12)
    # normal of a linear wave: (-∂η/∂x, -∂η/∂y, 1) normalised
    slope = -a * k * math.sin(theta) * d
    n = np.array([-slope[0], -slope[1], 1.0])
    np.testing.assert_allclose(sea.normal(x, y, t)[0], n / np.linalg.norm(n), atol=1e-12)


def test_finite_depth_kinematics_at_the_bed_have_no_vertical_velocity():
    depth = 5.0
    k = float(spectra.wavenumber(2 * math.pi / 6.0, depth))
    sea = DirectWaveField(from_arrays(0.2, k, 0.0, 0.0, 0.0, depth), depth=depth)
    assert sea.components.omega[0] == pytest.approx(2 * math.pi / 6.0)
    vel = sea.velocity(np.array([1.0]), np.array([0.0]), np.array([-depth]), 0.8)
    assert vel[0, 2] == pytest.approx(0.0, abs=1e-12)
    theta = k * 1.0 - sea.components.omega[0] * 0.8
    assert vel[0, 0] == pytest.approx(0.2 * sea.components.omega[0] * math.cos(theta) / math.sinh(k * depth))


def test_ramp_scales_the_sea_from_zero():
    sea = DirectWaveField(from_arrays(1.0, 0.1, 0.0, 0.0, 0.0), ramp_time_s=2.0)
    assert sea.elevation(np.array([0.0]), np.array([0.0]), 0.0)[0] == 0.0
    expected = (1 - math.exp(-1.0)) * math.cos(-math.sqrt(spectra.G * 0.1) * 2.0)
    assert sea.elevation(np.array([0.0]), np.array([0.0]), 2.0)[0] == pytest.approx(expected)


def test_random_sea_same_seed_same_sea_and_variance():
    def make(seed):
        return random_sea(
            lambda w: spectra.jonswap(w, 2.0, 8.0, 3.3),
            2 * math.pi / 8,
            np.random.default_rng(seed),
            n=200,
            direction=0.2,
            spreading_s=8.0,
        )

    a, b, c = make(1), make(1), make(2)
    for name in ("amplitude", "kx", "ky", "omega", "phase"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert not np.array_equal(a.phase, c.phase)
    assert 4 * math.sqrt(a.variance) == pytest.approx(2.0, rel=0.01)
    np.testing.assert_allclose(a.phase_speed, np.sqrt(spectra.G / a.k), rtol=1e-12)


def test_vrx_pms_components():
    c = vrx_pms_components(gain=0.6, period=6.0, direction=0.5, angle=0.4, scale=1.1, steepness=0.3)
    wp = 2 * math.pi / 6.0
    np.testing.assert_allclose(c.omega, wp * np.array([1 / 1.1, 1.0, 1.1]))
    np.testing.assert_allclose(c.direction, [0.1, 0.5, 0.9])
    d_omega = np.array([wp * (1 - 1 / 1.1), wp * (1.1 - 1 / 1.1) / 2, wp * (1.1 - 1)])
    np.testing.assert_allclose(c.amplitude, 0.6 * np.sqrt(2 * spectra.vrx_pms(c.omega, 6.0) * d_omega))
    np.testing.assert_allclose(c.steepness, np.minimum(1, 0.3 / (c.amplitude * c.k * 3)))
    np.testing.assert_allclose(c.phase_speed, np.sqrt(spectra.G / c.k), rtol=1e-12)
