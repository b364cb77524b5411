"""Build the ocean of a scenario from its `environment` section and the simulation's "ocean" random stream.

The stream is split into independent child streams for waves, wind and current, so that changing the wind does
not change the sea. Same section and same stream state → the identical ocean.
"""

from __future__ import annotations

import math
from functools import partial

import numpy as np

from usvsim.config import environment as cfg
from usvsim.ocean import spectra
from usvsim.ocean.components import from_arrays, random_sea, vrx_pms_components
from usvsim.ocean.current import Current
from usvsim.ocean.direct import DirectWaveField
from usvsim.ocean.fft import FFTWaveField, cascade_sizes, directional_spectrum
from usvsim.ocean.field import WaveField
from usvsim.ocean.ocean import Ocean
from usvsim.ocean.presets import SEA_STATES, VRX_PRESETS
from usvsim.ocean.wind import Wind


def build_ocean(env: cfg.Environment, rng: np.random.Generator, dt_s: float = 0.01) -> Ocean:
    """The scenario's ocean; `dt_s` (s) is the step of the gust and current processes (use the physics step)."""
    wave_rng, wind_rng, current_rng = rng.spawn(3)
    wind = build_wind(env.wind, wind_rng, dt_s)
    c = env.current
    current = Current(
        c.speed_mps,
        c.direction_rad,
        current_rng,
        c.speed_std_mps,
        c.direction_std,
        c.time_constant_s,
        c.shear.profile,
        c.shear.depth_m,
        dt_s,
    )
    waves = build_waves(env, wind, wave_rng)
    return Ocean(waves, wind, current, env.water_level_m)


def build_wind(w: cfg.WindConfig, rng: np.random.Generator, dt_s: float) -> Wind:
    """Wind from its section; a VRX `preset` fills the keys the section does not set."""
    speed, gain, direction = w.speed_mps, w.gust_gain, w.direction_rad
    if w.preset is not None:
        if w.preset not in VRX_PRESETS:
            raise ValueError(f"unknown wind preset {w.preset!r}; choose one of {sorted(VRX_PRESETS)}")
        p, given = VRX_PRESETS[w.preset], w.model_fields_set
        speed = speed if "speed_mps" in given else p.wind_speed_mps
        gain = gain if "gust_gain" in given else p.wind_gust_gain
        direction = direction if given & {"direction", "direction_deg"} else p.wind_direction
    return Wind(speed, direction, rng, gain, w.gust_time_constant_s, dt_s)


def build_waves(env: cfg.Environment, wind: Wind, rng: np.random.Generator) -> WaveField | None:
    """The wave field of `env.sea` (None for a flat sea)."""
    builder = _BUILDERS[env.sea.type]
    return builder(env.sea, env, wind, rng)


def _spectral(sea, env, spectrum: partial, tp, direction, rng) -> WaveField:
    omega_p = 2.0 * math.pi / tp
    r = sea.realization
    if r.method == "direct":
        depth = env.water_depth_m or math.inf
        comps = random_sea(
            spectrum, omega_p, rng, r.components, direction, sea.spreading_s, sea.choppiness, depth
        )
        return DirectWaveField(comps, depth, env.ramp_time_s)
    sizes = r.tile_sizes_m or cascade_sizes(2.0 * math.pi * spectra.G / omega_p**2, r.bands, r.resolution)
    # the spectrum is a partial of a module function: its name and keywords say which function it is
    key = ("directional", spectrum.func.__module__, spectrum.func.__qualname__, tuple(sorted(spectrum.keywords.items())),
           direction, sea.spreading_s)  # fmt: skip
    return FFTWaveField(
        directional_spectrum(spectrum, direction, sea.spreading_s),
        sizes,
        rng,
        r.resolution,
        sea.choppiness,
        env.ramp_time_s,
        r.gaussian_amplitudes,
        spectrum_key=key,
    )


def _jonswap(sea: cfg.JonswapSea, env, wind, rng):
    gamma = sea.gamma if sea.gamma is not None else spectra.dnv_gamma(sea.hs_m, sea.tp_s)
    spectrum = partial(spectra.jonswap, hs=sea.hs_m, tp=sea.tp_s, gamma=gamma)
    return _spectral(sea, env, spectrum, sea.tp_s, sea.direction_rad, rng)


def _pierson_moskowitz(sea: cfg.PiersonMoskowitzSea, env, wind: Wind, rng):
    direction = sea.direction_rad
    if sea.hs_m is not None:
        hs, tp = sea.hs_m, sea.tp_s
        assert tp is not None  # validated: hs_m and tp_s come together
    else:
        speed = sea.wind_speed_mps if sea.wind_speed_mps is not None else wind.speed_mps
        if sea.from_wind and sea.direction is None and sea.direction_deg is None:
            direction = wind.direction
        hs, tp = spectra.pm_from_wind(speed)
        if hs == 0.0:
            return None
    return _spectral(sea, env, partial(spectra.pierson_moskowitz, hs=hs, tp=tp), tp, direction, rng)


def _sea_state(sea: cfg.SeaStateSea, env, wind, rng):
    state = SEA_STATES[sea.code]
    if state.hs_m == 0.0:
        return None
    gamma = spectra.dnv_gamma(state.hs_m, state.tp_s)
    spectrum = partial(spectra.jonswap, hs=state.hs_m, tp=state.tp_s, gamma=gamma)
    return _spectral(sea, env, spectrum, state.tp_s, sea.direction_rad, rng)


def _phillips(sea: cfg.PhillipsSea, env, wind: Wind, rng):
    """HDRP bands: repetition size L0, L0/ratio (ratio = lerp 5..50 over L0 = 250..5000 m), a 10 m ripple band.

    The middle tile is clamped into [L0·32/N, 10 m·N/32] so that neighbouring tiles differ by at most N/32.
    """
    swell_speed, direction = sea.wind_speed_mps, sea.direction_rad
    if sea.from_wind:
        swell_speed, direction = wind.speed_mps, wind.direction
    ratio = 5.0 + 45.0 * (sea.repetition_size_m - 250.0) / 4750.0
    step = sea.resolution / (4 * FFTWaveField.CELLS_PER_WAVELENGTH)
    middle = min(max(sea.repetition_size_m / ratio, sea.repetition_size_m / step), 10.0 * step)
    sizes = (sea.repetition_size_m, middle, 10.0)
    speeds = (swell_speed, swell_speed, sea.ripples_wind_speed_mps)
    chaos = (sea.chaos, sea.chaos, sea.ripples_chaos)

    def spectrum(kx, ky, band):
        return sea.band_dimmers[band] ** 2 * spectra.phillips(kx, ky, speeds[band], direction, chaos[band])

    key = ("phillips", tuple(sea.band_dimmers), speeds, direction, chaos)
    return FFTWaveField(spectrum, sizes, rng, sea.resolution, sea.choppiness, env.ramp_time_s, spectrum_key=key)


def _wavenumber(c: cfg.WaveComponentConfig, depth: float) -> float:
    """k (rad/m) of a component given by its wavelength or else (validated: exactly one is set) its period."""
    if c.wavelength_m:
        return 2.0 * math.pi / c.wavelength_m
    assert c.period_s is not None
    return float(spectra.wavenumber(2 * math.pi / c.period_s, depth))


def _components(sea: cfg.ComponentsSea, env, wind, rng):
    depth = env.water_depth_m or math.inf
    k = [_wavenumber(c, depth) for c in sea.components]
    comps = from_arrays(
        [c.amplitude_m for c in sea.components],
        k,
        [c.direction_rad for c in sea.components],
        [c.phase for c in sea.components],
        [c.steepness for c in sea.components],
        depth,
    )
    return DirectWaveField(comps, depth, env.ramp_time_s)


def _vrx(sea: cfg.VrxSea, env, wind, rng):
    p = VRX_PRESETS[sea.preset or "defaults"]
    given = sea.model_fields_set & {"direction", "direction_deg"}
    comps = vrx_pms_components(
        sea.gain if sea.gain is not None else p.gain,
        sea.period_s if sea.period_s is not None else p.period_s,
        sea.direction_rad if given else p.direction,
        sea.angle if sea.angle is not None else p.angle,
        sea.scale if sea.scale is not None else p.scale,
        sea.steepness,
        sea.phase,
    )
    return DirectWaveField(comps, math.inf, env.ramp_time_s)


_BUILDERS = {
    "flat": lambda sea, env, wind, rng: None,
    "jonswap": _jonswap,
    "pierson_moskowitz": _pierson_moskowitz,
    "sea_state": _sea_state,
    "phillips": _phillips,
    "regular": _components,
    "gerstner": _components,
    "vrx": _vrx,
}
