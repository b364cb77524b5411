"""Velocity controller design and behaviour without the simulator: gains from the vessel's parameters,
feed-forward from its damping model, reference model limits, anti-windup, reset."""

from __future__ import annotations

import numpy as np
import pytest

from usvsim.control import PlantModel, ThrusterLayout, VelocityController
from usvsim.control.velocity import AxisTuning, actuator_time_constant
from usvsim.vessels import otter, wamv


def design(build, tuning=None):
    model = build()
    plant = PlantModel.from_body_model(model)
    layout = ThrusterLayout.from_thrusters(model.thrusters, plant.com_flu_m)
    return VelocityController.design(plant, layout, actuator_time_constant(model.thrusters), tuning), plant


def test_gains_follow_lambda_tuning():
    ctrl, plant = design(wamv.build)
    lam = 1.0 / (4 * 0.3)  # slowest actuator: the azimuth servo, 0.3 s
    surge = ctrl.tuning("surge")
    assert surge.bandwidth_rad_s == pytest.approx(lam)
    assert surge.kp == pytest.approx(lam * plant.mass_kg)
    assert ctrl.tuning("yaw").kp == pytest.approx(lam * plant.inertia_z_kgm2)
    assert ctrl.active.tolist() == [True, True, True]
    otter_ctrl, _ = design(otter.build)
    assert otter_ctrl.tuning("surge").bandwidth_rad_s == pytest.approx(2.0)  # 1/(4·0.1 s), capped at 2
    assert otter_ctrl.active.tolist() == [True, False, True]  # no sway authority


def test_max_speed_from_own_model_matches_fossen_u_max():
    ctrl, _ = design(otter.build)
    assert ctrl.max_velocity[0] == pytest.approx(
        2 * 119.682 / 77.55443, rel=1e-9
    )  # Fossen's U_max, 3.0864 m/s
    wamv_ctrl, _ = design(wamv.build)
    assert wamv_ctrl.max_velocity[0] == pytest.approx(
        (-100 + np.sqrt(100**2 + 4 * 150 * 1000)) / 300, rel=1e-9
    )


def test_steady_state_output_is_the_damping_feedforward():
    ctrl, plant = design(otter.build)
    nu = np.array([1.5, 0.0, 0.1])
    ctrl.update(nu, nu, 0.05)
    tau = ctrl.update(nu, nu, 0.05)
    expected = plant.damping(nu)
    assert tau[0] == pytest.approx(expected[0])
    assert tau[2] == pytest.approx(expected[2])
    assert tau[1] == 0.0


def test_reference_respects_acceleration_and_velocity_limits():
    ctrl, _ = design(
        wamv.build, (AxisTuning(max_acceleration=0.3, max_velocity=1.0), AxisTuning(), AxisTuning())
    )
    refs = []
    for _ in range(400):
        ctrl.update(np.zeros(3), [5.0, 0.0, 0.0], 0.05)
        refs.append(ctrl.reference[0])
    assert np.max(np.diff(refs)) <= 0.3 * 0.05 + 1e-12
    assert max(refs) <= 1.0 + 1e-12 and refs[-1] == pytest.approx(1.0, abs=1e-3)


def test_back_calculation_keeps_the_command_at_what_the_actuators_deliver():
    ctrl, _ = design(otter.build)
    free, _ = design(otter.build)
    nu, cap = np.array([0.5, 0.0, 0.0]), 100.0  # held below the reference; thrust saturates at 100 N
    for _ in range(600):
        tau = ctrl.update(nu, [1.0, 0.0, 0.0], 0.05)
        ctrl.report_achieved(np.minimum(tau, cap), 0.05)
        tau_free = free.update(nu, [1.0, 0.0, 0.0], 0.05)
    # back-calculation equilibrium at tracking rate λ: Ki e dt = λ dt (τ - cap), Ki = λ d  ⇒  τ - cap = d e
    assert tau[0] - cap == pytest.approx(77.55443 * 0.5, rel=1e-6)
    assert tau_free[0] > 2 * cap  # without anti-windup the integrator runs to its clamp


def test_reset_restarts_from_the_measurement():
    ctrl, _ = design(wamv.build)
    for _ in range(50):
        ctrl.update(np.zeros(3), [1.0, 0.0, 0.1], 0.05)
    ctrl.reset()
    ctrl.update(np.array([0.7, 0.0, 0.0]), [0.7, 0.0, 0.0], 0.05)
    np.testing.assert_allclose(ctrl.reference, [0.7, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(ctrl.integrators, 0.0, atol=1e-9)


@pytest.mark.parametrize(
    "field, value",
    [("kp", float("nan")), ("ki", float("inf")), ("kp", -1.0), ("bandwidth_rad_s", float("nan")),
     ("bandwidth_rad_s", -1.0), ("max_velocity", 0.0), ("reference_bandwidth_rad_s", "fast")],
)  # fmt: skip
def test_python_tuning_is_checked_like_the_scenario_keys(field, value):
    """From Python a NaN gain gave a controller that left the WAM-V at rest under a 1 m/s command, a negative
    bandwidth drove it backwards at 1.18 m/s, and max_velocity=0 was read as "derive it" (the YAML keys refuse all)."""
    from usvsim.core.errors import InputError

    with pytest.raises(InputError, match=f"AxisTuning.{field} must be a finite number"):
        AxisTuning(**{field: value})
    assert AxisTuning(kp=0.0, ki=0.0).kp == 0.0  # zero feedback gains are a choice


def test_unknown_allocator_names_the_choices():
    from usvsim.control import VesselController
    from usvsim.core.errors import InputError

    with pytest.raises(InputError, match="allocator 'qp': choose 'unconstrained' or 'constrained'"):
        VesselController.for_model(wamv.build(), allocator="qp")  # was KeyError: 'qp'
