"""Froude–Krylov pressure under waves against the closed form of a fixed box in a regular wave.

Box L x B x draft T (L along the wave, x), fixed, deep water, Airy wave η = a cos(kx - ωt) of small steepness.
Only the flat bottom (z = -T) carries vertical force, so the linear heave force about its static value is
F_z(t) = ρ g a e^{-kT} B ∫ cos(kx - ωt) dx over [-L/2, L/2] = ρ g a B e^{-kT} (2/k) sin(kL/2) cos ωt
(the Froude–Krylov force, e.g. Newman, Marine Hydrodynamics §6; Journée & Massie, Offshore Hydromechanics §6).
The hydrostatic column ρ g (η - z) instead gives the same without e^{-kT}.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh

from usvsim.hydro.hydrostatics import HullSet
from usvsim.ocean.components import from_arrays
from usvsim.ocean.direct import DirectWaveField
from usvsim.ocean.pressure import surface_and_dynamic_head

RHO, G = 1025.0, 9.81
L, B, T, A = 4.0, 1.0, 0.5, 0.01  # m; a k <= 0.03: linear theory holds to ~1 %


def heave_amplitude(wavelength_m: float, froude_krylov: bool) -> float:
    """Amplitude (N) of the first harmonic of F_z(t) - ρ g L B T over one wave period, box fixed at draft T."""
    k = 2 * math.pi / wavelength_m
    waves = DirectWaveField(from_arrays(A, k, 0.0, 0.0, 0.0))
    box = trimesh.creation.box(extents=(L, B, 1.0))
    box.apply_translation((0.0, 0.0, 0.5 - T))
    verts, faces = trimesh.remesh.subdivide_to_size(box.vertices, box.faces, max_edge=wavelength_m / 40)
    hulls = HullSet([(verts, faces)])
    com = np.zeros((1, 3))
    omega = math.sqrt(G * k)
    times = np.linspace(0.0, 2 * math.pi / omega, 24, endpoint=False)
    fz = []
    for t in times:
        eta, zeta = surface_and_dynamic_head(waves, verts[:, 0], verts[:, 1], verts[:, 2], t)
        head = zeta - verts[:, 2] if froude_krylov else np.zeros(0)
        fz.append(hulls.compute(np.ascontiguousarray(verts), eta, com, RHO, G, head).force[0, 2])
    dyn = np.asarray(fz) - RHO * G * L * B * T
    return 2 * abs(np.mean(dyn * np.exp(1j * omega * times)))


def closed_form(wavelength_m: float, decay: bool = True) -> float:
    k = 2 * math.pi / wavelength_m
    return RHO * G * A * B * (math.exp(-k * T) if decay else 1.0) * (2 / k) * abs(math.sin(k * L / 2))


@pytest.mark.parametrize("wavelength_m", [3.0, 6.0, 200.0])
def test_box_heave_force_matches_the_froude_krylov_closed_form(wavelength_m):
    """Short waves (λ = 3 m: e^{-kT} = 0.35) and long ones (λ = 200 m: 0.98), within 2 %."""
    assert heave_amplitude(wavelength_m, True) == pytest.approx(closed_form(wavelength_m), rel=0.02)


def test_hydrostatic_column_has_no_depth_decay():
    """The `hydrostatic` option is the long-wave limit at every wavelength (here 2.9x too much at λ = 3 m)."""
    assert heave_amplitude(3.0, False) == pytest.approx(closed_form(3.0, decay=False), rel=0.02)


def test_fft_sea_pressure_decays_like_the_sum_of_its_components():
    """FFT tiles: ζ = η at z = η (pressure 0 on the moving surface); below, each band decays with its mean
    wavenumber. Reference: the exact per-component sum (DirectWaveField) of the same bins. Compared: the
    attenuation std(ζ(η - d)) / std(η) at d = 3 m and 8 m (within 4 %; the FFT heights themselves differ
    from the sum by interpolation, so levels are compared as ratios)."""
    from usvsim.config.environment import Environment
    from usvsim.ocean import build_ocean

    env = Environment.model_validate({"sea": {"type": "sea_state", "code": 4}})
    waves = build_ocean(env, np.random.default_rng(1)).waves
    exact = DirectWaveField(waves.components(1e-5))
    x, y = np.random.default_rng(2).uniform(0.0, 50.0, (2, 200))
    for field in (waves, exact):
        eta = field.elevation(x, y, 3.0)
        assert surface_and_dynamic_head(field, x, y, eta, 3.0)[1] == pytest.approx(eta, abs=1e-12)
    ratios = {}
    for name, field in (("fft", waves), ("exact", exact)):
        eta = field.elevation(x, y, 3.0)
        ratios[name] = [np.std(surface_and_dynamic_head(field, x, y, eta - d, 3.0)[1]) / np.std(eta) for d in (3, 8)]
    assert ratios["fft"] == pytest.approx(ratios["exact"], rel=0.04)
    assert ratios["exact"][1] < 0.5  # the decay is real: 8 m down, under half of the surface's motion
