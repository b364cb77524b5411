"""Ready-made inputs for the viewer: a scripted lap of the harbour and the harbour with waves."""

from __future__ import annotations

from importlib import resources

import yaml

# A closed lap of the `harbor` scenario for the WAM-V (≈ 67 m, back within 0.5 m of the start, clear of
# the buoys): east past the Otter, starboard U-turn, west along y ≈ −9, starboard U-turn back to the start.
HARBOR_LAP = (
    (0.0, "w", "press"),
    (9.0, "d", "press"),
    (14.4, "d", "release"),
    (23.0, "d", "press"),
    (27.2, "d", "release"),
    (31.0, "w", "release"),
)
HARBOR_LAP_SECONDS = 34.0
WAVES = {"sea": {"type": "jonswap", "hs_m": 0.6, "tp_s": 4.0, "realization": {"resolution": 64}}}


def harbor_with_waves(environment: dict | None = None):
    """The built-in `harbor` scenario with a JONSWAP sea (Hs 0.6 m, Tp 4 s) instead of calm water."""
    from usvsim.config.loader import parse_scenario

    data = yaml.safe_load((resources.files("usvsim.scenarios") / "harbor.yaml").read_text())
    data["environment"] = environment or WAVES
    data["name"] = "harbor_waves"
    return parse_scenario(data, "harbor+waves")
