"""Scenario `rendering` section: the look of every camera, the viewer and documentation pictures.

Sun, sky, fog and haze, water appearance and camera effects. None of it changes physics or LiDAR, and
depth and segmentation images never depend on it. A running simulation holds the current look in
`sim.look` (a frozen `Rendering`); change it between frames with `sim.look = sim.look.updated({...})`
(validated like the file). Angles are degrees here because people write them; colours are linear RGB 0–1.
"""

from __future__ import annotations

import math
from datetime import UTC, datetime
from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Field, field_validator, model_validator

from usvsim.config.base import NonNegativeFloat, PositiveFloat, Section, _list_to_tuple

Unit = Annotated[float, Field(ge=0, le=1)]
Rgb = Annotated[tuple[Unit, Unit, Unit], BeforeValidator(_list_to_tuple)]
SUN_FIELDS = ("azimuth_deg", "elevation_deg")


class Sun(Section):
    """The sun's direction, either as angles or from a UTC time at the scenario's geodetic origin."""

    azimuth_deg: Annotated[float, Field(ge=0, lt=360)] = Field(default=135.0, description="where the sun stands, "
                                                                "compass: clockwise from north (90 = east)")
    elevation_deg: Annotated[float, Field(ge=-90, le=90)] = Field(default=45.0, description="above the horizon; < 0: "
                                                                  "below (dusk/night)")
    utc: str | None = Field(default=None, description='ISO 8601 time, e.g. "2025-06-21T05:30:00Z": sets azimuth and '
                            "elevation")
    intensity: NonNegativeFloat = Field(default=1.0, description="multiplier on the daylight model (sun and sky)")
    color: Rgb | None = Field(default=None, description="linear RGB 0-1; null: from the elevation (white at noon, "
                              "orange near the horizon)")

    @field_validator("utc")
    @classmethod
    def _iso_time(cls, value):
        if value is not None:
            utc_datetime(value)
        return value

    @model_validator(mode="after")
    def _angles_or_time(self):
        if self.utc is not None and self.model_fields_set & set(SUN_FIELDS):
            raise ValueError("give either 'utc' or azimuth_deg/elevation_deg, not both")
        return self


class Sky(Section):
    """Preetham daylight sky; turbidity 2 is very clear air, 3 clear, 6 hazy, 10 thick haze."""

    turbidity: Annotated[float, Field(ge=1.7, le=10)] = 2.5


class Fog(Section):
    """Exponential height fog. `visibility_m`: meteorological visibility at sea level (contrast falls to 2 %;
    extinction 3.912 / visibility); None = no fog. Density falls by e every `height_falloff_m` upward."""

    visibility_m: PositiveFloat | None = None
    color: Rgb = (0.72, 0.76, 0.80)
    height_falloff_m: PositiveFloat = 40.0


class Haze(Section):
    """Aerial perspective of clear air: distant objects and the horizon fade toward the sky's horizon colour."""

    visibility_m: PositiveFloat = 25_000.0


class WaterLook(Section):
    """Appearance of the sea surface (the surface itself comes from the ocean the physics uses)."""

    color: Rgb = Field(default=(0.012, 0.09, 0.12), description="linear RGB 0-1 of light scattered back from "
                       "inside the water body")
    foam: NonNegativeFloat = Field(default=1.0, description="whitecap and waterline foam amount (0: none)")
    glint: NonNegativeFloat = Field(default=1.0, description="strength of the sun's specular reflection")
    short_waves: Annotated[float, Field(ge=0, le=4)] = Field(default=1.0, description="slopes of the waves shorter "
                                                             "than the physics resolves (drawn as normals only; 0: none)")
    # (the spectrum's tail); rendering/detail.py
    wake_s: Annotated[float, Field(ge=0, le=60)] = Field(default=30.0, description="foam trails behind moving "
                                                         "vessels: seconds of track (0: none)")
    clarity_m: PositiveFloat | None = Field(default=2.0, description="path in the water over which the seabed or a "
                                            "hull fades by e; null: opaque")


class CameraLook(Section):
    """Effects of a real camera, applied to every camera's RGB image (never to depth or labels)."""

    exposure_ev: Annotated[float, Field(ge=-10, le=10)] = Field(default=0.0, description="+1 doubles the brightness")
    vignetting: Annotated[float, Field(ge=0, le=1)] = Field(default=0.25, description="brightness lost at the corners")
    blur_sigma_px: Annotated[float, Field(ge=0, le=20)] = Field(default=0.0, description="Gaussian defocus blur")
    noise_stddev: Annotated[float, Field(ge=0, le=1)] = Field(default=0.0, description="on top of each camera's own "
                                                              "rgb_noise_stddev")
    droplets: Annotated[float, Field(ge=0, le=1)] = Field(default=0.0, description="water drops on the lens (0: none, "
                                                          "1: ~60 drops)")
    motion_blur_ms: Annotated[float, Field(ge=0, le=200)] = Field(default=0.0, description="exposure smearing the "
                                                                  "camera's motion (0: off)")


class Rain(Section):
    """Rain between the camera and the scene: streaks in camera images and extinction added to the fog
    (0.25·R^0.63 per km); `slant_deg` tilts the streaks (wind)."""

    rate_mm_h: Annotated[float, Field(ge=0, le=200)] = Field(default=0.0, description="0: no rain; 2.5 light, "
                                                             "10 moderate, 50 heavy")
    slant_deg: Annotated[float, Field(ge=-60, le=60)] = 10.0


class Lights(Section):
    """Navigation lights (COLREG sidelights, masthead and stern lights on vessels; flashing lights on red, green
    and yellow buoys): `auto` lights them from sunset to sunrise and in fog under 2 km visibility."""

    navigation: Literal["auto", "on", "off"] = "auto"
    intensity: Annotated[float, Field(ge=0, le=100)] = Field(default=1.0, description="multiplier on the lamps' "
                                                             "brightness")


class Rendering(Section):
    """`renderer: shader` draws sky, water, fog and camera effects with GLSL shaders around MuJoCo's geoms;
    `renderer: mujoco` (the default while the shader is ~1.5x slower on a CPU, docs/rendering.md) is MuJoCo's
    plain fixed-function look (flat painted sky, tinted height field)."""

    renderer: Literal["shader", "mujoco"] = "mujoco"
    sun: Sun = Sun()
    sky: Sky = Sky()
    fog: Fog = Fog()
    haze: Haze = Haze()
    water: WaterLook = WaterLook()
    camera: CameraLook = CameraLook()
    lights: Lights = Lights()
    rain: Rain = Rain()
    shadows: bool = Field(default=False, description="the sun's shadows of geoms on geoms (MuJoCo's shadow map) "
                          "and on the water (boxes)")
    materials: bool = Field(default=True, description="gloss by material class: painted hull, metal, rubber, buoy "
                            "plastic, wood, concrete")

    def updated(self, changes: dict[str, Any]) -> Rendering:
        """A copy with nested `changes` merged in (e.g. {"sun": {"elevation_deg": 5}}), validated strictly."""
        return Rendering.model_validate(_merge(self.model_dump(exclude_unset=True), changes))


def _merge(base: dict, changes: dict) -> dict:
    out = dict(base)
    for key, value in changes.items():
        out[key] = _merge(out.get(key) or {}, value) if isinstance(value, dict) else value
    if "sun" in changes and isinstance(changes["sun"], dict):  # new angles replace a time and vice versa
        if "utc" in changes["sun"]:
            out["sun"] = {k: v for k, v in out["sun"].items() if k not in SUN_FIELDS}
        elif set(changes["sun"]) & set(SUN_FIELDS):
            out["sun"].pop("utc", None)
    return out


def utc_datetime(text: str) -> datetime:
    """Parse an ISO 8601 time; a time without zone is UTC."""
    stamp = datetime.fromisoformat(text.replace("Z", "+00:00"))
    return stamp.replace(tzinfo=UTC) if stamp.tzinfo is None else stamp.astimezone(UTC)


def solar_angles_deg(utc: str, latitude_deg: float, longitude_deg: float) -> tuple[float, float]:
    """(compass azimuth, elevation) of the sun in degrees (NOAA's low-precision formulas, ~0.5° here)."""
    t = utc_datetime(utc)
    day = t.timetuple().tm_yday
    hours = t.hour + t.minute / 60 + t.second / 3600
    g = 2 * math.pi / 365 * (day - 1 + (hours - 12) / 24)  # fractional year, rad
    eqtime = 229.18 * (0.000075 + 0.001868 * math.cos(g) - 0.032077 * math.sin(g)
                       - 0.014615 * math.cos(2 * g) - 0.040849 * math.sin(2 * g))  # fmt: skip
    decl = (0.006918 - 0.399912 * math.cos(g) + 0.070257 * math.sin(g) - 0.006758 * math.cos(2 * g)
            + 0.000907 * math.sin(2 * g) - 0.002697 * math.cos(3 * g) + 0.00148 * math.sin(3 * g))  # fmt: skip
    hour_angle = math.radians((hours * 60 + eqtime + 4 * longitude_deg) / 4 - 180)
    lat = math.radians(latitude_deg)
    cos_zen = math.sin(lat) * math.sin(decl) + math.cos(lat) * math.cos(decl) * math.cos(hour_angle)
    zen = math.acos(max(-1.0, min(1.0, cos_zen)))
    az = math.degrees(
        math.atan2(
            math.sin(hour_angle), math.cos(hour_angle) * math.sin(lat) - math.tan(decl) * math.cos(lat)
        )
    )
    return (az + 180.0) % 360.0, 90.0 - math.degrees(zen)


def sun_angles_deg(look: Rendering, latitude_deg: float, longitude_deg: float) -> tuple[float, float]:
    """The sun's (compass azimuth, elevation) in degrees for a look at a geodetic origin."""
    if look.sun.utc is not None:
        return solar_angles_deg(look.sun.utc, latitude_deg, longitude_deg)
    return look.sun.azimuth_deg, look.sun.elevation_deg


def sun_direction_enu(azimuth_deg: float, elevation_deg: float) -> tuple[float, float, float]:
    """Unit vector toward the sun in the world frame (ENU) from compass azimuth and elevation."""
    az, el = math.radians(azimuth_deg), math.radians(elevation_deg)
    return math.cos(el) * math.sin(az), math.cos(el) * math.cos(az), math.sin(el)
