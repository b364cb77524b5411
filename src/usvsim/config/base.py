"""Base class of every scenario section and shared field types: strict, frozen, unknown keys rejected.

No float anywhere in a scenario may be NaN or infinite (`allow_inf_nan=False` reaches every nested
float, tuple and dict value). The physical limits below are documented in docs/limits.md.
"""

from __future__ import annotations

from typing import Annotated, TypeVar

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field


class KeyedValueError(ValueError):
    """A section validator's error about one key inside the section: `key` (relative to the section, e.g.
    `vessels[1].name`) joins the error's key path, so the line points at the value to fix (a cross-field check
    was reported at the section, e.g. the duplicate names at the file's top level)."""

    def __init__(self, key: str, message: str):
        super().__init__(message)
        self.key = key


class Section(BaseModel):
    """A scenario section. Unknown keys are errors; values are immutable once loaded."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True, allow_inf_nan=False)


def _list_to_tuple(value):
    return tuple(value) if isinstance(value, list) else value


MAX_COORDINATE_M = 100_000.0  # positions and offsets: 100 km around the world origin
MAX_SIZE_M = 10_000.0  # one object's extent
MIN_SIZE_M = 0.001  # 1 mm: smaller parts are below MuJoCo's geometric tolerances
MAX_ANGLE_DEG = 3600.0  # ten turns; angles are wrapped anyway

Coordinate = Annotated[float, Field(ge=-MAX_COORDINATE_M, le=MAX_COORDINATE_M)]
Vec2 = Annotated[tuple[Coordinate, Coordinate], BeforeValidator(_list_to_tuple)]
Vec3 = Annotated[tuple[Coordinate, Coordinate, Coordinate], BeforeValidator(_list_to_tuple)]
PositiveFloat = Annotated[float, Field(gt=0)]
NonNegativeFloat = Annotated[float, Field(ge=0)]
Size = Annotated[float, Field(ge=MIN_SIZE_M, le=MAX_SIZE_M)]
Size3 = Annotated[tuple[Size, Size, Size], BeforeValidator(_list_to_tuple)]
AngleDeg = Annotated[float, Field(ge=-MAX_ANGLE_DEG, le=MAX_ANGLE_DEG)]
MassKg = Annotated[float, Field(ge=1e-3, le=1e9)]  # 1 g to a million tonnes
Inertia = Annotated[float, Field(ge=1e-6, le=1e13)]  # kg m^2
Inertia3 = Annotated[tuple[Inertia, Inertia, Inertia], BeforeValidator(_list_to_tuple)]
Scale = Annotated[float, Field(ge=1e-3, le=1e3)]
LatLonDeg = Annotated[tuple[Annotated[float, Field(ge=-90, le=90)], Annotated[float, Field(ge=-180, le=180)]],
                      BeforeValidator(_list_to_tuple)]  # fmt: skip


class LatLon(Section):
    """Optionally placed by geography: `latlon` [latitude, longitude] in degrees (WGS-84) replaces the
    position's x and y (the ENU point at the scenario's geodetic origin); z stays as given."""

    latlon: LatLonDeg | None = Field(default=None, description="[latitude_deg, longitude_deg], WGS-84; replaces x, y")


class GeoPose(LatLon):
    """`latlon` plus an optional compass `heading_deg` (clockwise from north), which replaces `yaw_deg`."""

    heading_deg: AngleDeg | None = Field(default=None, description="compass heading, degrees clockwise from north")


class PoseDeg(Section):
    """Position (m) and roll/pitch/yaw (degrees, REP 103) of a frame in a parent frame the subclass names."""

    position: Vec3 = Field(default=(0.0, 0.0, 0.0), description="[x, y, z] in the parent frame, m")
    roll_deg: AngleDeg = Field(default=0.0, description="about the parent's x, applied first; then pitch about its y, "
                                    "then yaw about its z (fixed axes, REP 103)")
    pitch_deg: AngleDeg = Field(default=0.0, description="about y; positive tips +x down (right-handed about y)")
    yaw_deg: AngleDeg = Field(default=0.0, description="about z, counter-clockwise seen from above")


_Item = TypeVar("_Item")
TupleOf = Annotated[tuple[_Item, ...], BeforeValidator(_list_to_tuple)]
"""A strict tuple field that also accepts a YAML list: `TupleOf[PositiveFloat]` (a generic alias, so that
type checkers read it as `tuple[float, ...]`)."""
