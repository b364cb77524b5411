"""Base class of every scenario section and shared field types: strict, frozen, unknown keys rejected."""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field


class Section(BaseModel):
    """A scenario section. Unknown keys are errors; values are immutable once loaded."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True)


def _list_to_tuple(value):
    return tuple(value) if isinstance(value, list) else value


Vec2 = Annotated[tuple[float, float], BeforeValidator(_list_to_tuple)]
Vec3 = Annotated[tuple[float, float, float], BeforeValidator(_list_to_tuple)]
PositiveFloat = Annotated[float, Field(gt=0)]
NonNegativeFloat = Annotated[float, Field(ge=0)]


class LatLon(Section):
    """Optionally placed by geography: `latlon` [latitude, longitude] in degrees (WGS-84) replaces the
    position's x and y (the ENU point at the scenario's geodetic origin); z stays as given."""

    latlon: Vec2 | None = Field(None, description="[latitude_deg, longitude_deg], WGS-84; replaces x, y")


class GeoPose(LatLon):
    """`latlon` plus an optional compass `heading_deg` (clockwise from north), which replaces `yaw_deg`."""

    heading_deg: float | None = Field(None, description="compass heading, degrees clockwise from north")


class PoseDeg(Section):
    """Position (m) and roll/pitch/yaw (degrees, REP 103) of a frame in a parent frame the subclass names."""

    position: Vec3 = (0.0, 0.0, 0.0)
    roll_deg: float = 0.0
    pitch_deg: float = 0.0
    yaw_deg: float = 0.0


def tuple_of(item):
    """A strict tuple field that also accepts a YAML list."""
    return Annotated[tuple[item, ...], BeforeValidator(_list_to_tuple)]
