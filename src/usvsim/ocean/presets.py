"""Named sea states: the WMO sea-state code 0–9 and VRX's (gain, period, direction) worlds.

Sea-state code: Hs is the middle of the WMO code's height band (code 9: "over 14 m", 16 m taken), Tp the most
probable modal period of the open-ocean (North Atlantic) sea-state table of NATO STANAG 4194 / Lee & Bales for
codes 2–9; code 1 (rippled, 0–0.1 m) uses Tp = 2 s; code 0 is flat.
VRX: the 2023 Phase-2 trial levels (peer-simulators.md §2.7; for gust gain the middle of the table's range, the wind
speed and direction of a named example world) and the defaults of its worlds (§2.5). Directions: wave and wind
direction the waves/wind travel toward, rad CCW from east.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class SeaState:
    code: int
    description: str
    hs_m: float
    tp_s: float


SEA_STATES: dict[int, SeaState] = {
    s.code: s
    for s in (
        SeaState(0, "calm (glassy)", 0.0, 0.0),
        SeaState(1, "calm (rippled), 0-0.1 m", 0.05, 2.0),
        SeaState(2, "smooth (wavelets), 0.1-0.5 m", 0.3, 7.5),
        SeaState(3, "slight, 0.5-1.25 m", 0.875, 7.5),
        SeaState(4, "moderate, 1.25-2.5 m", 1.875, 8.8),
        SeaState(5, "rough, 2.5-4 m", 3.25, 9.7),
        SeaState(6, "very rough, 4-6 m", 5.0, 12.4),
        SeaState(7, "high, 6-9 m", 7.5, 15.0),
        SeaState(8, "very high, 9-14 m", 11.5, 16.4),
        SeaState(9, "phenomenal, over 14 m", 16.0, 20.0),
    )
}


@dataclass(frozen=True)
class VrxPreset:
    """VRX wavefield (gain, period, direction, angle, scale) and wind (mean, gust gain, direction)."""

    gain: float
    period_s: float
    direction: float
    wind_speed_mps: float = 0.0
    wind_gust_gain: float = 0.0
    wind_direction: float = 0.0
    angle: float = 0.4
    scale: float = 1.1


VRX_PRESETS: dict[str, VrxPreset] = {
    "defaults": VrxPreset(1.0, 5.0, 0.0),  # wavefield SDF defaults
    "calm": VrxPreset(0.0, 4.0, 0.0),
    "moderate": VrxPreset(0.6, 6.0, math.pi / 4, 5.0, 3.0, math.radians(120.0)),  # stationkeeping1
    "rough": VrxPreset(0.8, 6.0, math.pi / 2, 7.0, 2.8, math.radians(265.0)),  # stationkeeping2
    "short_steep": VrxPreset(2.0, 2.0, 0.0, 9.0, 4.5, math.radians(355.0)),  # follow_path2
    "sydney_regatta": VrxPreset(0.3, 5.0, 0.0),  # task-world default
    "ocean_waves_classic": VrxPreset(0.1, 5.0, 0.0, scale=1.5),  # classic `ocean_waves` macro
}


def hs_tp(sea) -> tuple[float | None, float | None]:
    """The significant height and peak period (m, s) a sea section (`config.environment`) asks for: a WMO code's
    (None for the flat code 0), or its own `hs_m` and `tp_s` where it gives them (None where it does not)."""
    if sea.type == "sea_state":
        state = SEA_STATES[sea.code]
        return (state.hs_m, state.tp_s) if sea.code > 0 else (None, None)
    return getattr(sea, "hs_m", None), getattr(sea, "tp_s", None)
