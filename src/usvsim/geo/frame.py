"""The world frame on the Earth: WGS-84 ↔ local ENU at the scenario's geodetic origin, and any CRS → ENU.

ENU here is the exact topocentric frame of PROJ (`+proj=topocentric`, WGS-84 ellipsoid): x east, y north,
z up, metres, through geocentric coordinates, so round trips are exact to float precision and heights are
ellipsoidal. Input CRSs with only 2D coordinates are taken at the origin's altitude.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from usvsim.core.errors import UsvsimError

WGS84_3D = "EPSG:4979"  # latitude, longitude (deg), ellipsoidal height (m)


class GeoError(UsvsimError):
    """A geospatial file or setting is unusable; the message names the file."""


def require(module: str):
    """Import one of the geo extra's packages, or say how to install it."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        raise GeoError(f"geo: {module} is missing; install the extra: pip install 'usvsim[geo]'") from None


def parse_crs(value, source: str):
    """A pyproj CRS from a file's CRS or a scenario's `crs:` string, or a GeoError naming `source`."""
    from pyproj import CRS
    from pyproj.exceptions import CRSError

    try:
        return CRS.from_user_input(value)
    except CRSError as exc:
        reason = str(exc).split(": (", 1)[0]  # PROJ's own wording follows in parentheses
        raise GeoError(f"{source}: {value!s} is not a coordinate reference system pyproj knows ({reason})") from None


def same_crs(file_crs, given, source: str) -> bool:
    """Whether the scenario's `crs:` names the file's own CRS (axis order aside)."""
    return parse_crs(file_crs, source).equals(parse_crs(given, f"{source}: crs"), ignore_axis_order=True)


@lru_cache(maxsize=16)
def _pipeline(lat_deg: float, lon_deg: float, alt_m: float):
    Transformer = require("pyproj").Transformer

    return Transformer.from_pipeline(
        "+proj=pipeline +step +proj=axisswap +order=2,1 +step +proj=unitconvert +xy_in=deg +xy_out=rad "
        "+step +proj=cart +ellps=WGS84 "
        f"+step +proj=topocentric +ellps=WGS84 +lat_0={lat_deg!r} +lon_0={lon_deg!r} +h_0={alt_m!r}"
    )


class GeoFrame:
    """Conversions between WGS-84 (lat, lon in degrees, ellipsoidal height in m) and the world ENU (m)."""

    def __init__(self, latitude_deg: float, longitude_deg: float, altitude_m: float = 0.0):
        self.origin = (float(latitude_deg), float(longitude_deg), float(altitude_m))
        self._to_enu = _pipeline(*self.origin)

    def to_enu(self, lat_deg, lon_deg, alt_m=None) -> np.ndarray:
        """ENU positions (n, 3) of WGS-84 points (arrays or scalars); alt defaults to the origin's."""
        lat, lon = np.atleast_1d(np.asarray(lat_deg, float)), np.atleast_1d(np.asarray(lon_deg, float))
        alt = np.broadcast_to(self.origin[2] if alt_m is None else np.asarray(alt_m, float), lat.shape)
        x, y, z = self._to_enu.transform(lat, lon, alt.astype(float))
        return np.column_stack([x, y, z])

    def to_geodetic(self, x_m, y_m, z_m: float | np.ndarray = 0.0) -> np.ndarray:
        """(n, 3) latitude, longitude (deg) and ellipsoidal height (m) of ENU points."""
        x = np.atleast_1d(np.asarray(x_m, float))
        y = np.broadcast_to(np.asarray(y_m, float), x.shape).astype(float)
        z = np.broadcast_to(np.asarray(z_m, float), x.shape).astype(float)
        from pyproj.enums import TransformDirection

        lat, lon, alt = self._to_enu.transform(x, y, z, direction=TransformDirection.INVERSE)
        return np.column_stack([lat, lon, alt])

    def level_to_geodetic(self, x_m, y_m) -> np.ndarray:
        """(n, 3) latitude, longitude (deg) and height (m) of the points at ENU (x, y) that lie at the origin's
        ellipsoidal height: the inverse of `to_enu` for 2D data (files, `latlon`), which sits there. The tangent
        plane's point (z = 0) stands d²/2R higher, and its z = altitude_m above it (what rasters were sampled
        at) shifted lookups outward by altitude·d/R: 0.58 m at 10 km from an origin at 372 m (QA)."""
        x = np.atleast_1d(np.asarray(x_m, float))
        y = np.broadcast_to(np.asarray(y_m, float), x.shape).astype(float)
        z = -(x * x + y * y) / (2.0 * 6371008.8)  # the level surface's drop, within a few cm (mean Earth radius)
        z = z - (self.to_geodetic(x, y, z)[:, 2] - self.origin[2])  # one Newton step on the height: sub-mm
        return self.to_geodetic(x, y, z)

    def from_crs(self, crs, source: str):
        """A function (x, y) → ENU (x, y) for coordinates in `crs` (horizontal; at the origin's height)."""
        from pyproj import Transformer

        crs = parse_crs(crs, source)
        to_geo = Transformer.from_crs(crs, "EPSG:4326", always_xy=True)

        def convert(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            lon, lat = to_geo.transform(np.asarray(x, float), np.asarray(y, float))
            if not (np.all(np.abs(lon) <= 360.0) and np.all(np.abs(lat) <= 90.0)):  # 0..360 data is fine
                raise GeoError(f"{source}: coordinates outside the area of its CRS ({crs.name}); is the CRS right?")
            enu = self.to_enu(lat, lon)
            return enu[:, 0], enu[:, 1]

        return convert
