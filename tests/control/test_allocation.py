"""Thrust allocation against physics.md §5.4, random τ properties, limits, and scipy as an independent
reference for the box-constrained least squares."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import lsq_linear

from usvsim.config.vessel import Azimuth, Thruster, ThrustMap
from usvsim.control import ConstrainedAllocator, PseudoInverseAllocator, ThrusterLayout
from usvsim.control.boxqp import box_qp
from usvsim.control.layout import thrust_matrix
from usvsim.vessels import otter, wamv

OTTER_MAP = ThrustMap(type="quadratic", max_forward_n=119.682, max_reverse_n=66.708)


def two_azimuths() -> ThrusterLayout:
    az = Azimuth(min_deg=-180.0, max_deg=180.0)
    return ThrusterLayout.from_thrusters(
        [
            Thruster(name="t1", position=(-1.0, -0.5, 0.0), azimuth=az),
            Thruster(name="t2", position=(-1.0, 0.5, 0.0), azimuth=az),
        ]
    )


def otter_table_layout() -> ThrusterLayout:
    """§5.4's B = [[1, 1], [0.395, -0.395]] (Fossen's NED yaw sign): in FLU, thruster 1 at y = -0.395."""
    ts = [Thruster(name="t1", position=(0.0, -0.395, 0.0), thrust=OTTER_MAP),
          Thruster(name="t2", position=(0.0, 0.395, 0.0), thrust=OTTER_MAP)]  # fmt: skip
    return ThrusterLayout.from_thrusters(ts, weights=[0.0, 0.0])


def mixed_layout(azimuth_range_deg: float = 60.0) -> ThrusterLayout:
    """Two fixed mains, a bow tunnel thruster (mount yaw 90°) and a stern azimuth with a limited range."""
    m = ThrustMap(type="linear", max_forward_n=300.0, max_reverse_n=150.0)
    return ThrusterLayout.from_thrusters([
        Thruster(name="main_l", position=(-3.0, 0.8, 0.0), thrust=m),
        Thruster(name="main_r", position=(-3.0, -0.8, 0.0), thrust=m),
        Thruster(name="tunnel", position=(3.5, 0.0, 0.0), mount_yaw_deg=90.0,
                 thrust=ThrustMap(type="quadratic", max_forward_n=120.0, max_reverse_n=120.0)),
        Thruster(name="az", position=(-2.0, 0.0, 0.0), thrust=ThrustMap(type="glf", max_forward_n=250.0, max_reverse_n=100.0),
                 azimuth=Azimuth(min_deg=-azimuth_range_deg, max_deg=azimuth_range_deg)),
    ], com_flu_m=(0.2, 0.0, 0.3))  # fmt: skip


def test_two_azimuth_reference_numbers():
    layout = two_azimuths()
    np.testing.assert_allclose(layout.extended, [[1, 0, 1, 0], [0, 1, 0, 1], [0.5, -1, -0.5, -1]])
    alloc = PseudoInverseAllocator(layout, column_weights=[1, 1, 1, 1])
    np.testing.assert_allclose(alloc.pinv @ [100, 20, 10], [80, 10, 20, 10], atol=1e-9)
    out = alloc.allocate([100.0, 20.0, 10.0])
    np.testing.assert_allclose(out.thrust_n, [80.6226, 22.3607], atol=5e-5)
    np.testing.assert_allclose(np.degrees(out.angle_rad), [7.1250, 26.5651], atol=5e-5)
    weighted = PseudoInverseAllocator(layout, column_weights=[1, 1, 4, 4])
    np.testing.assert_allclose(weighted.pinv @ [100, 20, 10], [80, 16, 20, 4], atol=1e-9)


@pytest.mark.parametrize(
    ("tau", "unconstrained", "constrained", "achieved"),
    [
        ((200, 0), (100, 100), (100, 100), (200, 0)),
        ((200, 30), (137.9747, 62.0253), (119.682, 75.3802), (195.0622, 17.4992)),
        ((300, 60), (225.9494, 74.0506), (119.682, 119.682), (239.364, 0)),
    ],
)
def test_otter_box_constrained_table(tau, unconstrained, constrained, achieved):
    layout = otter_table_layout()
    full = (tau[0], 0.0, tau[1])
    np.testing.assert_allclose(
        PseudoInverseAllocator(layout).allocate(full).thrust_n, unconstrained, atol=5e-5
    )
    out = ConstrainedAllocator(layout, tau_weights=[1.0, 1.0, 1.0]).allocate(full)
    np.testing.assert_allclose(out.thrust_n, constrained, atol=5e-5)
    np.testing.assert_allclose(out.tau_achieved[[0, 2]], achieved, atol=5e-5)


def otter_layout():
    m = otter.build()
    return ThrusterLayout.from_thrusters(m.thrusters, m.com)


def wamv_layout():
    m = wamv.build()
    return ThrusterLayout.from_thrusters(m.thrusters, m.com)


def mixed_layout_full_range() -> ThrusterLayout:
    return mixed_layout(90.0)


@pytest.mark.parametrize("make", [two_azimuths, wamv_layout, mixed_layout_full_range, otter_layout])
def test_unconstrained_reproduces_random_tau(make):
    layout = make()
    alloc = PseudoInverseAllocator(layout)
    rng = np.random.default_rng(1)
    for _ in range(200):
        tau = rng.uniform(-1, 1, 3) * layout.capacity() * 0.5
        if not layout.is_fully_actuated():
            tau[1] = 0.0  # the attainable set of a twin-propeller boat has no sway
        out = alloc.allocate(tau)
        f = alloc.pinv @ tau
        assert np.abs(layout.extended @ f - tau).max() < 1e-6
        assert np.abs(thrust_matrix(layout.params, out.angle_rad) @ out.thrust_n - tau).max() < 1e-6


@pytest.mark.parametrize("make", [wamv_layout, mixed_layout, otter_layout])
def test_constrained_respects_every_limit(make):
    layout = make()
    p = layout.params
    alloc = ConstrainedAllocator(layout)
    rng = np.random.default_rng(2)
    dt = 0.05
    for _ in range(300):
        tau = rng.uniform(-1.5, 1.5, 3) * layout.capacity()
        angle_now = rng.uniform(p[:, 4], p[:, 5])
        out = alloc.allocate(tau, angle_now, None, dt)
        assert np.all(out.thrust_n <= p[:, 8] + 1e-9) and np.all(out.thrust_n >= -p[:, 9] - 1e-9)
        assert np.all(np.abs(out.u) <= 1.0)
        az = layout.azimuth
        assert np.all(out.angle_rad[az] >= p[az, 4] - 1e-12) and np.all(out.angle_rad[az] <= p[az, 5] + 1e-12)
        assert np.all(np.abs(out.angle_effective_rad - angle_now)[az] <= p[az, 6] * dt + 1e-12)
        np.testing.assert_allclose(
            layout.tau_from_thrusts(out.thrust_n, out.angle_effective_rad), out.tau_achieved, atol=1e-9
        )


def test_constrained_meets_attainable_tau_once_angles_settle():
    layout = wamv_layout()
    alloc = ConstrainedAllocator(layout)
    rng = np.random.default_rng(3)
    for _ in range(50):
        tau = rng.uniform(-0.1, 0.1, 3) * layout.capacity()
        for _ in range(100):  # the azimuths turn at their rate limit
            out = alloc.allocate(tau, dt=0.05)
        assert np.abs(out.tau_achieved - tau).max() < 1e-4 * np.abs(tau).max() + 1e-6


def test_thrust_rate_limit_bounds_the_change():
    m = ThrustMap(type="linear", max_forward_n=100.0, max_reverse_n=100.0)
    layout = ThrusterLayout.from_thrusters([Thruster(name="a", position=(-1.0, 0.5, 0.0), thrust=m, max_rate_n_s=50.0),
                                            Thruster(name="b", position=(-1.0, -0.5, 0.0), thrust=m, max_rate_n_s=50.0)])  # fmt: skip
    out = ConstrainedAllocator(layout).allocate([150.0, 0.0, 0.0], None, [10.0, 20.0], 0.1)
    np.testing.assert_allclose(out.thrust_n, [15.0, 25.0], atol=1e-9)


def test_constrained_matches_scipy_bounded_least_squares():
    """Fixed thrusters: the allocator's QP equals scipy's lsq_linear on the stacked, weighted problem."""
    layout = ThrusterLayout.from_thrusters(list(_fixed_only()))
    alloc = ConstrainedAllocator(layout)
    q, p = alloc.tau_weights, layout.params
    B = thrust_matrix(p, np.zeros(layout.n))
    A = np.vstack([np.sqrt(q)[:, None] * B, np.diag(np.sqrt(p[:, 12]) / p[:, 8])])
    rng = np.random.default_rng(4)
    for _ in range(100):
        tau = rng.uniform(-1.2, 1.2, 3) * layout.capacity()
        ref = lsq_linear(A, np.concatenate([np.sqrt(q) * tau, np.zeros(layout.n)]), bounds=(-p[:, 9], p[:, 8]),
                         method="bvls", tol=1e-14).x  # fmt: skip
        np.testing.assert_allclose(alloc.allocate(tau).thrust_n, ref, atol=1e-6 * p[:, 8].max())


def _fixed_only():
    m = ThrustMap(type="quadratic", max_forward_n=200.0, max_reverse_n=80.0)
    yield Thruster(name="l", position=(-2.0, 0.6, 0.0), thrust=m)
    yield Thruster(name="r", position=(-2.0, -0.6, 0.0), thrust=m)
    yield Thruster(name="bow", position=(2.0, 0.0, 0.0), mount_yaw_deg=90.0, thrust=m)
    yield Thruster(name="stern", position=(-2.5, 0.0, 0.0), mount_yaw_deg=90.0, thrust=m)


def test_box_qp_against_scipy_bvls():
    rng = np.random.default_rng(5)
    for _ in range(300):
        n, m = rng.integers(1, 9), rng.integers(1, 10)
        A, y = rng.normal(size=(m, n)), rng.normal(size=m) * 3
        lo, hi = -rng.uniform(0, 2, n), rng.uniform(0, 2, n)
        z = np.zeros(n)
        box_qp(A.T @ A + 1e-10 * np.eye(n), A.T @ y, lo, hi, z)
        ref = lsq_linear(A, y, bounds=(lo, hi), method="bvls", tol=1e-14).x
        assert 0.5 * np.sum((A @ z - y) ** 2) <= 0.5 * np.sum((A @ ref - y) ** 2) + 1e-9


def test_azimuth_holds_angle_at_zero_force_and_prefers_forward():
    layout = wamv_layout()
    alloc = ConstrainedAllocator(layout)
    out = alloc.allocate([0.0, 0.0, 0.0], np.full(4, 0.3), None, 0.05)
    np.testing.assert_allclose(out.angle_rad, 0.3)
    np.testing.assert_allclose(out.thrust_n, 0.0, atol=1e-9)
    ahead = alloc.allocate([400.0, 0.0, 0.0], np.zeros(4), None, 0.05)
    assert np.all(ahead.thrust_n > 0) and np.allclose(ahead.angle_rad, 0.0, atol=1e-6)
    astern = alloc.allocate([-150.0, 0.0, 0.0], np.zeros(4), None, 0.05)  # reverse, not a 180° swing
    assert np.all(astern.thrust_n < 0) and np.allclose(astern.angle_rad, 0.0, atol=1e-6)
    assert math.isclose(astern.tau_achieved[0], -150.0, rel_tol=1e-4)
