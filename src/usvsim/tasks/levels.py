"""Difficulty levels 0–2 as VRX's 2023 practice worlds set them (peer-simulators.md §2.7, `ocean.presets`).

0: calm (no waves, no wind) · 1: moderate (VRX gain 0.6, T 6 s, wind 5 m/s gusting) · 2: rough (gain 0.8,
T 6 s, wind 7 m/s). Waves are VRX's 3-component PMS wavefield (`sea: {type: vrx}`), cheap to evaluate.
`sea_state` overrides the sea with a WMO code (JONSWAP on 64 x 64 FFT tiles: the cheapest spectral
sea here, about 3x the speed of a 32-component direct sum on this machine) for sweeps and benchmarks. Lighting stays the default daylight at every level.
"""

from __future__ import annotations

from usvsim.core.errors import UsvsimError

LEVELS = {0: "calm", 1: "moderate", 2: "rough"}


def environment(difficulty: int, sea_state: int | None = None) -> dict:
    """The scenario `environment` section (a plain dict) of a difficulty level."""
    if isinstance(difficulty, bool) or difficulty not in LEVELS:  # True was level 1
        raise UsvsimError(f"difficulty must be one of {sorted(LEVELS)}, not {difficulty!r}")
    if sea_state is not None and (isinstance(sea_state, bool) or sea_state not in range(10)):
        raise UsvsimError(f"sea_state must be a WMO sea-state code 0-9 or None, not {sea_state!r}")
    preset = LEVELS[difficulty]
    sea = {"type": "flat"} if preset == "calm" else {"type": "vrx", "preset": preset}
    if sea_state is not None:
        sea = {"type": "flat"} if sea_state == 0 else {
            "type": "sea_state", "code": int(sea_state), "realization": {"method": "fft", "resolution": 64}}  # fmt: skip
    wind = {} if preset == "calm" else {"preset": preset}
    return {"sea": sea, "wind": wind}
