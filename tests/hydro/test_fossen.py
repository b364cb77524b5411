"""Fossen model: PVS matrices (physics.md §3.1), frame conversion, Coriolis form, reference point, VRX sets."""

from __future__ import annotations

import numpy as np
import pytest

from usvsim.hydro.fossen import (
    T6,
    FossenForces,
    FossenParameters,
    cross_flow,
    hoerner_cd,
    hydro_wrench,
    m2c,
    split_added_mass,
)
from usvsim.hydro.fossen_sets import VRX_CLASSIC, otter, otter_pvs, wamv_vrx

M_REF = np.array([[85.5, 0, 0, 0, -19.75, 0], [0, 162.5, 0, 19.75, 0, 12.25], [0, 0, 135.0, 0, -12.25, 0],
                  [0, 19.75, 0, 24.890485, 0, 5.540869], [-19.75, 0, -12.25, 0, 45.481621, 0],
                  [0, 12.25, 0, 5.540869, 0, 42.65145]])


def test_otter_matrices_match_pvs():
    o = otter_pvs()
    np.testing.assert_allclose(o.M_RB + o.M_A, M_REF, atol=6e-7)
    np.testing.assert_allclose(np.diag(o.D), [77.55443, 162.5, 605.40388, 62.06542, 266.59700, 42.65145], atol=6e-6)
    assert o.Dq[5] == pytest.approx(426.5145, abs=1e-4)
    assert (o.G[2, 2], o.G[2, 4], o.G[3, 3], o.G[4, 4]) == pytest.approx((7541.4375, 1508.2875, 967.2662, 2743.3705), abs=1e-4)
    assert o.cross_flow[2] == pytest.approx(1.004184, abs=1e-6) and o.cross_flow[1] == pytest.approx(0.195122, abs=1e-6)
    assert hoerner_cd(0.25, 0.195122) == pytest.approx(1.004184, abs=1e-6)


def wrench(p, nu, nu_dot):
    out = np.zeros(6)
    hydro_wrench(p.added_mass, p.linear_damping, np.asarray(p.quadratic_damping, float), np.asarray(p.cross_flow, float),
                 p.coriolis_added_mass, nu, nu_dot, out)
    return out


def test_wrench_equals_matrix_form_and_is_frame_covariant():
    rng = np.random.default_rng(0)
    p = otter().to_flu()
    for _ in range(5):
        nu, nu_dot = rng.normal(size=6), rng.normal(size=6)
        L, T, cd, rho = p.cross_flow
        y, n = 0.0, 0.0
        for x in np.linspace(-L / 2, L / 2, 21):  # 21 strips, dx = L/20
            u = nu[1] + x * nu[5]
            y -= 0.5 * rho * T * cd * abs(u) * u * L / 20
            n -= 0.5 * rho * T * cd * x * abs(u) * u * L / 20
        expected = (-p.added_mass @ nu_dot - m2c(p.added_mass, nu) @ nu - p.linear_damping @ nu
                    - np.asarray(p.quadratic_damping) * np.abs(nu) * nu + np.array([0, y, 0, 0, 0, n]))
        np.testing.assert_allclose(wrench(p, nu, nu_dot), expected, rtol=1e-12, atol=1e-10)
        # FRD → FLU once at load: τ_FLU(T6 ν) = T6 τ_FRD(ν)
        frd = otter()
        np.testing.assert_allclose(wrench(p, T6 @ nu, T6 @ nu_dot), T6 @ wrench(frd, nu, nu_dot), rtol=1e-12, atol=1e-10)


def test_cross_flow_uses_21_strips():
    y, n = cross_flow(1.0, 0.0, 2.0, 0.5, 1.0, 1000.0)
    assert y == pytest.approx(-0.5 * 1000 * 0.5 * 1.0 * 1.0 * 2.0 * 1.05)
    assert n == pytest.approx(0.0, abs=1e-12)


def test_vrx_sets_are_linear_plus_quadratic_without_coriolis():
    p = wamv_vrx(classic=True)
    nu = np.array([1.0, -0.5, 0.2, 0.1, -0.3, 0.4])
    expected = -(np.array(VRX_CLASSIC[0]) + np.array(VRX_CLASSIC[1]) * np.abs(nu)) * nu
    np.testing.assert_allclose(wrench(p, nu, np.ones(6)), expected, rtol=1e-14)
    main = wamv_vrx()
    assert wrench(main, np.array([2.0, 0, 0, 0, 0, 0]), np.zeros(6))[0] == pytest.approx(-(100 * 2 + 150 * 4))


def test_forces_reference_point_and_lagged_added_mass():
    p = FossenParameters(np.diag([10.0, 20.0, 30.0, 1.0, 2.0, 3.0]), np.diag([5.0] * 6), np.zeros(6),
                         reference_point=np.array([1.0, 0.0, 0.0]), coriolis_added_mass=False, frame="FLU")
    ff = FossenForces([p], [[0.0, 0.0, 0.0]])
    nu = np.array([[0.0, 0.0, 0.0, 0.0, 0.0, 0.5]])  # pure yaw about the CoM: sway 0.5 m/s at x = 1
    w = ff.compute(nu, 0.01).copy()
    assert w[0, 1] == pytest.approx(-5.0 * 0.5)
    assert w[0, 5] == pytest.approx(-5.0 * 0.5 + 1.0 * w[0, 1])  # moment moved from the reference point
    nu2 = nu.copy()
    nu2[0, 0] = 0.1  # surge acceleration 10 m/s² over the step
    w2 = ff.compute(nu2, 0.01)
    assert w2[0, 0] == pytest.approx(-10.0 * 10.0 - 5.0 * 0.1)


def test_split_added_mass_makes_the_otter_stable():
    ma = np.diag(otter().to_flu().added_mass)
    armature, rest, ratio = split_added_mass(ma, 80.0)
    assert ma[1] / 80.0 > 1.0  # the pure explicit form would diverge in sway
    assert ratio < 0.35
    np.testing.assert_allclose(armature + rest, ma)
    np.testing.assert_allclose(armature[3:], ma[3:])
