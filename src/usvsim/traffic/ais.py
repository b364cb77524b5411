"""AIS reports as NMEA 0183 `!AIVDM` sentences (pyais encodes the 6-bit payloads) and their reporting intervals.

Reporting intervals, ITU-R M.1371-5 Annex 1 table 1 (Class A) and Class B "CS" (carrier-sense) units:

| Class A ship's dynamic conditions                 | interval |
|---------------------------------------------------|----------|
| at anchor or moored, not moving faster than 3 kn  | 3 min    |
| at anchor or moored, moving faster than 3 kn      | 10 s     |
| 0-14 kn                                           | 10 s     |
| 0-14 kn and changing course                       | 3 1/3 s  |
| 14-23 kn                                          | 6 s      |
| 14-23 kn and changing course                      | 2 s      |
| > 23 kn (changing course or not)                  | 2 s      |
| Class B CS: not faster than 2 kn / faster         | 3 min / 30 s |
Static and voyage data (type 5; Class B: type 24 parts A and B): every 6 min.

"Changing course" here means a rate of turn above `TURNING_DEG_PER_MIN` (the standard leaves the threshold
to the equipment). A traffic ship is taken as moored when it moves slower than 0.1 kn (navigational status 5);
the own ship (a vehicle under its own control) always reports "under way using engine" (status 0), stopped or
not, and its reporting interval is that of the 0-14 kn rows when stopped.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from pyais.encode import encode_dict

KNOT_MPS = 1852.0 / 3600.0
STATIC_INTERVAL_S = 360.0
TURNING_DEG_PER_MIN = 5.0
MOORED_KN = 0.1
HEADING_NA = 511


def is_moored(sog_kn: float, moored: bool | None) -> bool:
    """`moored` as given; None: moored when slower than MOORED_KN (a traffic ship stopped)."""
    return sog_kn < MOORED_KN if moored is None else moored


def class_a_interval(sog_kn: float, turning: bool, moored: bool | None = None) -> float:
    """Seconds between Class A position reports (table above); `moored`: see `is_moored`."""
    if is_moored(sog_kn, moored):
        return 180.0 if sog_kn <= 3.0 else 10.0
    if sog_kn <= 14.0:
        return 10.0 / 3.0 if turning else 10.0
    if sog_kn <= 23.0:
        return 2.0 if turning else 6.0
    return 2.0


def class_b_interval(sog_kn: float) -> float:
    """Seconds between Class B (CS) position reports."""
    return 180.0 if sog_kn <= 2.0 else 30.0


@dataclass(frozen=True)
class Report:
    """One ship's dynamic state as AIS carries it: WGS-84 degrees, knots, degrees clockwise from north."""

    mmsi: int
    lat_deg: float
    lon_deg: float
    sog_kn: float
    cog_deg: float
    heading_deg: int  # HEADING_NA when unknown
    utc_second: int
    moored: bool | None = None  # Class A navigational status 5 (else 0); None: moored when slower than MOORED_KN

    @property
    def status(self) -> int:
        """Class A navigational status: 5 moored, 0 under way using engine."""
        return 5 if is_moored(self.sog_kn, self.moored) else 0


def _clip_cog(cog_deg: float) -> float:
    return round(cog_deg % 360.0, 1) % 360.0


def position_sentences(r: Report, ais_class: str, channel: str = "A") -> list[str]:
    """Type 1 (Class A, scheduled) or type 18 (Class B CS) position report, encoded by pyais (the reference;
    `position_sentence` below packs the same bits 6-7x faster and is what the publisher sends)."""
    return encode_dict(_position_fields(r, ais_class), talker_id="AI", sentence_type="VDM", radio_channel=channel)


def _position_fields(r: Report, ais_class: str) -> dict:
    data = {"mmsi": r.mmsi, "lat": r.lat_deg, "lon": r.lon_deg, "speed": min(r.sog_kn, 102.2),
            "course": _clip_cog(r.cog_deg), "heading": r.heading_deg, "second": r.utc_second}  # fmt: skip
    if ais_class == "A":
        # manoeuvre indicator 0 = not available (pyais's default, 3, is not defined by M.1371)
        return data | {"type": 1, "status": r.status, "turn": -128, "maneuver": 0}
    return data | {"type": 18, "cs": 1}


# ITU-R M.1371-5 annex 8 bit layouts (width, in order) of the two position reports; the values are pyais's
# scalings (speed and course in tenths truncated, positions in 1/10000 minute rounded), so the bits are pyais's
_TYPE1 = (6, 2, 30, 4, 8, 10, 1, 28, 27, 12, 9, 6, 2, 3, 1, 19)  # ... status, turn, speed, accuracy, lon, lat, ...
_TYPE18 = (6, 2, 30, 8, 10, 1, 28, 27, 12, 9, 6, 2, 1, 1, 1, 1, 1, 1, 1, 20)  # ... reserved, speed, ..., cs, ...
_ARMOR = tuple(chr(v + 48 if v < 40 else v + 56) for v in range(64))  # 6-bit values → payload characters
_ARMOR2 = tuple(a + b for a in _ARMOR for b in _ARMOR)  # 12-bit values → two characters
_XOR2 = tuple(ord(a) ^ ord(b) for a in _ARMOR for b in _ARMOR)  # their contribution to the NMEA checksum


def position_sentence(r: Report, ais_class: str, channel: str = "A") -> str:
    """The one `!AIVDM` sentence of `position_sentences(r, ais_class, channel)`, packed here (168 bits: one
    sentence, no fill bits); the tests check it against pyais bit for bit."""
    speed, course = int(min(r.sog_kn, 102.2) * 10.0), int(_clip_cog(r.cog_deg) * 10.0)
    lon, lat = round(r.lon_deg * 600000.0), round(r.lat_deg * 600000.0)
    if ais_class == "A":
        values = (1, 0, r.mmsi, r.status, -128, speed, 0, lon, lat, course, r.heading_deg, r.utc_second, 0, 0, 0, 0)
        widths = _TYPE1
    else:
        values = (18, 0, r.mmsi, 0, speed, 0, lon, lat, course, r.heading_deg, r.utc_second, 0, 1, 0, 0, 0, 0, 0, 0, 0)
        widths = _TYPE18
    bits = 0
    for w, v in zip(widths, values):
        bits = (bits << w) | (v & ((1 << w) - 1))
    pairs = [(bits >> shift) & 4095 for shift in range(156, -1, -12)]
    check = _HEAD_XOR[channel]
    for v in pairs:
        check ^= _XOR2[v]
    return f"!AIVDM,1,1,,{channel},{''.join([_ARMOR2[v] for v in pairs])},0*{check:02X}"


def _xor(text: str) -> int:
    out = 0
    for b in text.encode("ascii"):
        out ^= b
    return out


_HEAD_XOR = {c: _xor(f"AIVDM,1,1,,{c},,0") for c in "AB"}  # the checksum of a sentence less its payload


def _dimensions(length_m: float, beam_m: float) -> dict[str, int]:
    """Reference point at midship: whole metres to bow, stern, port, starboard (ITU-R M.1371 fields A, B, C, D:
    A + B is the length, C + D the beam), so that length and beam read back as the configured ones rounded to
    the nearest metre (halves up); an odd metre goes to the bow and to starboard. The fields' limits are 511, 511,
    63, 63 (the largest value means "that or more")."""
    length, beam = math.floor(length_m + 0.5), math.floor(beam_m + 0.5)
    stern, port = min(length // 2, 511), min(beam // 2, 63)
    return {"to_bow": min(length - length // 2, 511), "to_stern": stern, "to_port": port,
            "to_starboard": min(beam - beam // 2, 63)}  # fmt: skip


@functools.lru_cache(maxsize=4096)  # the same every 6 minutes: encode once per ship, sequence id and channel
def static_sentences(mmsi: int, name: str, ship_type: int, callsign: str, length_m: float, beam_m: float,
                     draft_m: float, ais_class: str, seq_id: int, channel: str = "A") -> list[str]:  # fmt: skip
    """Type 5 (Class A, two sentences) or type 24 parts A and B (Class B)."""
    shipname = name.upper().replace("_", " ")[:20]
    dims = _dimensions(length_m, beam_m)
    kw = {"talker_id": "AI", "sentence_type": "VDM", "radio_channel": channel}
    if ais_class == "A":
        # ITU-R M.1371-5 annex 8, message 5: AIS version 2 (this edition); no ETA: month 0, day 0, hour 24, minute 60 (pyais's
        # defaults, hour 0 and minute 0, read as an ETA of midnight)
        data = {"type": 5, "mmsi": mmsi, "ais_version": 2, "shipname": shipname, "callsign": callsign,
                "ship_type": ship_type, "draught": min(draft_m, 25.5), "epfd": 1, "month": 0, "day": 0, "hour": 24,
                "minute": 60, **dims}  # fmt: skip
        return encode_dict(data, seq_id=seq_id % 10, **kw)
    part_a = encode_dict({"type": 24, "mmsi": mmsi, "partno": 0, "shipname": shipname}, **kw)
    part_b = encode_dict({"type": 24, "mmsi": mmsi, "partno": 1, "ship_type": ship_type, "callsign": callsign,
                          **dims}, **kw)  # fmt: skip
    return part_a + part_b


WGS84_A, WGS84_F = 6378137.0, 1.0 / 298.257223563
WGS84_B = WGS84_A * (1.0 - WGS84_F)
WGS84_E2 = WGS84_F * (2.0 - WGS84_F)


def enu_to_latlon(east_m: float, north_m: float, lat0_deg: float, lon0_deg: float,
                  alt0_m: float = 0.0) -> tuple[float, float]:  # fmt: skip
    """WGS-84 latitude and longitude (degrees) of a point of the tangent plane (ENU, m, z = 0) at the origin
    (lat0, lon0, ellipsoidal height alt0): ENU → ECEF, then Bowring's closed form (sub-millimetre near the
    surface). The origin's height matters: without it a report 10 km out sat alt0·d/R off (0.58 m at 372 m).
    Plain floats: ~30x faster than pymap3d.enu2geodetic per call, which matters at one call per report."""
    phi, lam = math.radians(lat0_deg), math.radians(lon0_deg)
    sp, cp, sl, cl = math.sin(phi), math.cos(phi), math.sin(lam), math.cos(lam)
    n0 = WGS84_A / math.sqrt(1.0 - WGS84_E2 * sp * sp)
    x = (n0 + alt0_m) * cp * cl - sl * east_m - sp * cl * north_m
    y = (n0 + alt0_m) * cp * sl + cl * east_m - sp * sl * north_m
    z = (n0 * (1.0 - WGS84_E2) + alt0_m) * sp + cp * north_m
    p = math.hypot(x, y)
    theta = math.atan2(z * WGS84_A, p * WGS84_B)
    ep2 = (WGS84_A**2 - WGS84_B**2) / WGS84_B**2
    lat = math.atan2(z + ep2 * WGS84_B * math.sin(theta) ** 3, p - WGS84_E2 * WGS84_A * math.cos(theta) ** 3)
    return math.degrees(lat), math.degrees(math.atan2(y, x))


def _north_east(lat_deg, lon_deg):
    """Unit vectors (ECEF) of true north and east at geodetic (lat, lon) degrees (arrays broadcast)."""
    phi, lam = np.radians(lat_deg), np.radians(lon_deg)
    sp, cp, sl, cl = np.sin(phi), np.cos(phi), np.sin(lam), np.cos(lam)
    return np.stack([-sp * cl, -sp * sl, cp], axis=-1), np.stack([-sl, cl, np.zeros_like(sl)], axis=-1)


def true_bearing_deg(lat_deg, lon_deg, grid_deg, lat0_deg: float, lon0_deg: float):
    """True bearing (degrees clockwise from true north, [0, 360)) at the point (lat, lon) of the world's horizontal
    direction whose grid bearing is `grid_deg` (degrees clockwise from the world's y axis, which is true north at
    the origin (lat0, lon0) only). The meridians converge: 20 km east of an origin at 59.4° N true north is 0.30°
    west of the y axis (Δλ·sin φ to first order), more than an AIS course's 0.1° resolution. Exact for the ENU
    tangent plane: the direction is taken in ECEF and measured in the point's own north-east plane."""
    n0, e0 = _north_east(lat0_deg, lon0_deg)
    n, e = _north_east(lat_deg, lon_deg)
    g = np.radians(grid_deg)
    d = np.sin(g)[..., None] * e0 + np.cos(g)[..., None] * n0
    return np.degrees(np.arctan2((d * e).sum(-1), (d * n).sum(-1))) % 360.0


def grid_bearing_deg(lat_deg, lon_deg, true_deg, lat0_deg: float, lon0_deg: float):
    """Inverse of `true_bearing_deg`: the grid bearing (degrees clockwise from the world's y axis, [0, 360)) of the
    direction at (lat, lon) whose true bearing is `true_deg` (to ~1e-12 degrees within the world's limits)."""
    grid = np.asarray(true_deg, dtype=float)
    for _ in range(3):  # the map is a rotation by the convergence, up to a distortion of ~(d/R)²: converges at once
        grid = grid - (((true_bearing_deg(lat_deg, lon_deg, grid, lat0_deg, lon0_deg) - true_deg) + 180.0) % 360.0
                       - 180.0)  # fmt: skip
    return grid % 360.0


def heading_deg(true_deg: float) -> int:
    """An AIS true heading in whole degrees (0..359) from a true bearing in degrees."""
    return int(round(true_deg)) % 360
