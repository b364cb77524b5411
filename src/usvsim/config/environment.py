"""Scenario `environment` section: sea (waves), wind, current, water level, start-up ramp.

Directions are where waves, wind or current travel toward, radians counter-clockwise from east (ENU);
`direction_deg` is the same in degrees (VRX worlds give wind in degrees). Give one of the two, not both.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import Discriminator, Field, Tag, model_validator

from usvsim.config.base import NonNegativeFloat, PositiveFloat, Section, TupleOf

UnitFloat = Annotated[float, Field(ge=0, le=1)]
Choppiness = Annotated[float, Field(ge=0, le=2)]
Resolution = Literal[8, 16, 32, 64, 128, 256, 512, 1024, 2048]  # FFT tile size N (a power of two)


class Directed(Section):
    direction: float | None = Field(default=None, description="toward which it travels (not where it comes from), "
                                    "counter-clockwise from east, rad; default 0 (toward east)")
    direction_deg: float | None = Field(default=None, description="the same in degrees (90 = toward north); give one")

    @model_validator(mode="after")
    def _one_direction(self):
        if self.direction is not None and self.direction_deg is not None:
            raise ValueError("give either 'direction' (rad) or 'direction_deg', not both")
        return self

    @property
    def direction_rad(self) -> float:
        """Direction toward which it travels, rad CCW from east (0 when none is given)."""
        if self.direction_deg is not None:
            return math.radians(self.direction_deg)
        return self.direction if self.direction is not None else 0.0


class FFTRealization(Section):
    """FFT tiles (cascades); tile sizes default to 10 peak wavelengths, each next one 0.95 N/32 times smaller (3.8
    at the default N = 128), at most 7.3 times.

    `resolution` trades accuracy for speed: each band is transformed only at its snapshot times (every
    0.2-1.2 s at N = 128 in sea state 4, blended in time within 1e-3 of sigma, see docs/seas.md), so N
    mostly sets the cost of a snapshot (~4x per doubling) and the bilinear error between tile vertices
    (~1.4 % of sigma at 256, ~4x that at 128; the mean variance loss is compensated)."""

    method: Literal["fft"] = "fft"
    resolution: Resolution = 128
    tile_sizes_m: Annotated[TupleOf[PositiveFloat], Field(min_length=1)] | None = Field(
        default=None, description="tile sides (m), largest first; default: fitted to the sea (10 peak wavelengths)")
    bands: Annotated[int, Field(ge=1, le=6)] = 3
    gaussian_amplitudes: bool = False

    @model_validator(mode="after")
    def _bands_fit(self):
        if self.tile_sizes_m is not None and "bands" in self.model_fields_set and self.bands != len(self.tile_sizes_m):
            raise ValueError(f"bands {self.bands} with {len(self.tile_sizes_m)} tile_sizes_m: give one of them "
                             "(the tiles are the bands)")  # fmt: skip
        # neighbouring tiles differ at most N/32 times (ocean/fft.py): below N = 64 the default cascade cannot step down
        if self.tile_sizes_m is None and self.bands > 1 and self.resolution < 64:
            raise ValueError(f"resolution {self.resolution} allows one band only: set bands: 1, or resolution >= 64")
        return self


class DirectRealization(Section):
    """Direct sum of `components` components, one per frequency bin (exact and unbounded, cost ∝ components)."""

    method: Literal["direct"]
    components: Annotated[int, Field(ge=1, le=4096)] = 128


def _realization_method(value) -> str:
    """The `method` tag of a realization; `fft` when the key is left out."""
    if isinstance(value, dict):
        return value.get("method", "fft")
    return getattr(value, "method", "fft")


Realization = Annotated[
    Annotated[FFTRealization, Tag("fft")] | Annotated[DirectRealization, Tag("direct")],
    Discriminator(_realization_method),
]


class SpectralSea(Directed):
    """Common keys of spectral seas: cos-2s spreading exponent s (None = long-crested, direct only)."""

    spreading_s: PositiveFloat | None = Field(default=10.0, description="the exponent s of cos-2s spreading "
                                              "(dimensionless; larger is narrower; null: long-crested)")  # fmt: skip
    choppiness: Choppiness = 0.0
    realization: Realization = FFTRealization()

    @model_validator(mode="after")
    def _fft_needs_spreading(self):
        if self.spreading_s is None and self.realization.method == "fft":
            raise ValueError("a long-crested sea (spreading_s: null) needs realization: {method: direct}")
        return self


class FlatSeaConfig(Section):
    """A flat, still sea (no waves; wind and current still act)."""

    type: Literal["flat"] = "flat"


# Physical bounds of a wind sea: sea-state code 9 starts at Hs 14 m and the largest measured Hs is about 20 m;
# peak periods beyond 40 s and fully developed seas of winds beyond 35 m/s (PM: Hs = 0.21 U² / g ≈ 26 m) are not
# seas the spectra describe.
SigWaveHeight = Annotated[float, Field(gt=0, le=30, description="significant wave height (m), at most 30")]
PeakPeriod = Annotated[float, Field(gt=0, le=40, description="spectral peak period (s), at most 40")]


class JonswapSea(SpectralSea):
    """A JONSWAP wind sea from Hs and Tp."""

    type: Literal["jonswap"]
    hs_m: SigWaveHeight
    tp_s: PeakPeriod
    gamma: Annotated[float, Field(ge=1, le=10)] | None = Field(default=None, description="peak enhancement γ; "
                                                                "null: the DNV rule from Hs and Tp")


class PiersonMoskowitzSea(SpectralSea):
    """From Hs and Tp, or fully developed from a wind speed (19.5 m), or `from_wind` (the scenario's wind)."""

    type: Literal["pierson_moskowitz"]
    hs_m: SigWaveHeight | None = None
    tp_s: PeakPeriod | None = None
    wind_speed_mps: Annotated[float, Field(gt=0, le=35, description="wind speed at 19.5 m (m/s), at most 35")] | None = None
    from_wind: bool = False

    @model_validator(mode="after")
    def _one_source(self):
        sources = [
            self.hs_m is not None and self.tp_s is not None,
            self.wind_speed_mps is not None,
            self.from_wind,
        ]
        if sum(sources) != 1 or (self.hs_m is None) != (self.tp_s is None):
            raise ValueError("give exactly one of: hs_m and tp_s, wind_speed_mps, or from_wind: true")
        return self


class SeaStateSea(SpectralSea):
    """WMO sea-state code 0–9 as a JONSWAP sea (Hs, Tp from `usvsim.ocean.presets`; γ by the DNV rule)."""

    type: Literal["sea_state"]
    code: Annotated[int, Field(ge=0, le=9)]


class PhillipsSea(Directed):
    """HDRP-like ocean: three FFT bands (two swell bands, ripples), Phillips spectrum per band."""

    type: Literal["phillips"]
    wind_speed_mps: NonNegativeFloat = 21.0 / 3.6
    chaos: UnitFloat = 0.0
    ripples_wind_speed_mps: NonNegativeFloat = 2.57 / 3.6
    ripples_chaos: UnitFloat = 0.44
    band_dimmers: Annotated[TupleOf[UnitFloat], Field(min_length=3, max_length=3)] = (1.0, 1.0, 1.0)
    repetition_size_m: Annotated[float, Field(ge=250, le=5000)] = 500.0
    resolution: Resolution = 256
    choppiness: Choppiness = 0.6
    from_wind: bool = False

    @model_validator(mode="after")
    def _bands_fit(self):
        need = 32.0 * math.sqrt(self.repetition_size_m / 10.0)  # tiles L0 → middle → 10 m, each step at most N/32
        if self.resolution < need:
            least = 1 << math.ceil(math.log2(need))
            raise ValueError(f"resolution {self.resolution} is too coarse for repetition_size_m {self.repetition_size_m:g}: "
                             f"its three bands down to 10 m need resolution >= {least}")  # fmt: skip
        return self


class WaveComponentConfig(Directed):
    """One regular component: amplitude and either wavelength or period; Gerstner steepness Q (0 = Airy)."""

    amplitude_m: NonNegativeFloat
    wavelength_m: PositiveFloat | None = None
    period_s: PositiveFloat | None = None
    phase: float = 0.0
    steepness: UnitFloat = 0.0

    @model_validator(mode="after")
    def _one_length(self):
        if (self.wavelength_m is None) == (self.period_s is None):
            raise ValueError("give exactly one of wavelength_m and period_s")
        return self


class ComponentsSea(Section):
    """Explicit components, summed directly: `regular` (usually Airy) or `gerstner` (same keys)."""

    type: Literal["regular", "gerstner"]
    components: Annotated[TupleOf[WaveComponentConfig], Field(min_length=1)]


PRESETS = "defaults, calm, moderate, rough, short_steep, sydney_regatta, ocean_waves_classic"  # VRX_PRESETS' names


def _known_preset(preset: str | None) -> None:
    from usvsim.ocean.presets import VRX_PRESETS  # here: usvsim.ocean imports this module

    if preset is not None and preset not in VRX_PRESETS:
        raise ValueError(f"unknown VRX preset {preset!r}; choose one of {sorted(VRX_PRESETS)}")


class VrxSea(Directed):
    """VRX "PMS" wavefield; a `preset` (usvsim.ocean.presets.VRX_PRESETS) fills the keys not given."""

    type: Literal["vrx"]
    preset: str | None = Field(default=None, description=f"a VRX world's waves: {PRESETS}")
    gain: NonNegativeFloat | None = None
    period_s: PositiveFloat | None = None
    angle: float | None = None
    scale: Annotated[float, Field(gt=1)] | None = None
    steepness: NonNegativeFloat = 0.0
    phase: float = 0.0

    @model_validator(mode="after")
    def _preset(self):
        _known_preset(self.preset)
        return self


Sea = Annotated[
    FlatSeaConfig | JonswapSea | PiersonMoskowitzSea | SeaStateSea | PhillipsSea | ComponentsSea | VrxSea,
    Field(discriminator="type"),
]


class WindConfig(Directed):
    """Mean wind plus VRX-form Gauss–Markov gusts (gain K, time constant τ; gust std K/√(2τ))."""

    speed_mps: NonNegativeFloat = 0.0
    gust_gain: NonNegativeFloat = 0.0
    gust_time_constant_s: PositiveFloat = 2.0
    preset: str | None = Field(default=None, description=f"a VRX world's wind (mean, gust gain, direction fill the "
                                                         f"keys not given): {PRESETS}")  # fmt: skip

    @model_validator(mode="after")
    def _preset(self):  # refused here, at environment.wind.preset (it was reported at environment.sea)
        _known_preset(self.preset)
        return self


class ShearConfig(Section):
    """How the current falls off with depth below the surface (`uniform`: not at all)."""

    profile: Literal["uniform", "linear", "exponential", "power"] = "uniform"
    depth_m: PositiveFloat = 10.0


class CurrentConfig(Directed):
    """Surface current; Gauss–Markov variation of speed and direction; depth profile."""

    speed_mps: NonNegativeFloat = 0.0
    speed_std_mps: NonNegativeFloat = 0.0
    direction_std: NonNegativeFloat = 0.0
    time_constant_s: PositiveFloat = 60.0
    shear: ShearConfig = ShearConfig()


class Environment(Section):
    """Sea, wind and current; every direction is the one toward which it travels, counter-clockwise from east."""

    sea: Sea = Field(default=FlatSeaConfig(), description="waves; default flat")
    wind: WindConfig = WindConfig()
    current: CurrentConfig = CurrentConfig()
    water_level_m: float = Field(default=0.0, ge=-1000, le=1000, description="z of the still water in the world frame")
    water_depth_m: Annotated[float, Field(gt=0, le=11_000)] | None = Field(
        default=None, description="for finite-depth waves (direct realization only); null: deep water")
    ramp_time_s: NonNegativeFloat = Field(default=2.0, description="time constant τ of the waves' start-up ramp "
                                          "1 - exp(-t/τ) on every amplitude; 0: none")
