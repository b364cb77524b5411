"""Wind loads: directions, quadratic scaling with air density, VRX form."""

from __future__ import annotations

import numpy as np
import pytest

from usvsim.hydro.wind import FOSSEN, VRX, wind_wrenches

COEF = np.array([[2.0, 6.0, 5.0, 0.7, 0.8, 0.1]])


def load(kind, wind, vcom=(0.0, 0.0, 0.0), yaw=0.0, rho=1.225):
    c, s = np.cos(yaw), np.sin(yaw)
    rot = np.array([[[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]])
    out = np.zeros((1, 6))
    wind_wrenches(np.array([kind]), COEF, rho, rot, np.array([vcom], float), np.array([wind], float), out)
    return out[0]


def test_fossen_head_and_beam_wind():
    head = load(FOSSEN, (-10.0, 0.0, 0.0))
    assert head[0] == pytest.approx(-0.5 * 1.225 * 100 * 2.0 * 0.7) and abs(head[1]) < 1e-12
    beam = load(FOSSEN, (0.0, 10.0, 0.0))  # wind blowing toward +y (port)
    assert beam[1] == pytest.approx(0.5 * 1.225 * 100 * 6.0 * 0.8) and abs(beam[0]) < 1e-9
    # a boat moving in still air feels the same as still boat in the opposite wind; quadratic in speed
    np.testing.assert_allclose(load(FOSSEN, (0, 0, 0), vcom=(0.0, -10.0, 0.0)), beam, atol=1e-9)
    np.testing.assert_allclose(load(FOSSEN, (0.0, 20.0, 0.0)), 4 * beam, atol=1e-9)
    np.testing.assert_allclose(load(FOSSEN, (0.0, 10.0, 0.0), rho=2.45), 2 * beam, atol=1e-9)
    # the body frame turns with the boat: heading north, a northward wind is a tail wind
    tail = load(FOSSEN, (0.0, 10.0, 0.0), yaw=np.pi / 2)
    assert tail[0] == pytest.approx(0.5 * 1.225 * 100 * 2.0 * 0.7)


def test_vrx_form():
    w = load(VRX, (3.0, -4.0, 0.0))
    np.testing.assert_allclose(w, [0.7 * 9, -0.8 * 16, 0, 0, 0, -2 * 0.1 * 3 * -4], atol=1e-12)
