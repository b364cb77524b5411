"""Domain randomization: a YAML file of distributions over the look, the scene and the environment.

```yaml
version: 1
per: frame                # frame: new values every frame | episode: every `frames_per_episode` frames
frames_per_episode: 1
look:                     # dotted paths into the scenario's `rendering:` section (docs/rendering.md)
  sun.azimuth_deg: {uniform: [0, 360]}
  fog.visibility_m: {choice: [150, 300, 600]}
scene:                    # the keys of SCENE below
  buoy_offset_m: {normal: [0, 2]}
environment:              # dotted paths into the scenario's `environment:`; drawn once per run
  sea.type: jonswap
  sea.hs_m: {uniform: [0.8, 1.2]}
```

A value is a constant or one distribution: `{uniform: [low, high]}`, `{normal: [mean, stddev]}` (with an
optional `clip: [low, high]`) or `{choice: [a, b, ...]}`. Every draw comes from one generator seeded by the
run's seed, in a fixed order, so the same seed gives the same values.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
import yaml
from pydantic import Field, ValidationError

from usvsim.config.base import Section
from usvsim.core.errors import UsvsimError

SCENE = {  # scene parameters: what each one changes (added to the scenario's value)
    "buoy_offset_m": "horizontal shift of each buoy, x and y drawn separately (m)",
    "vessel_offset_m": "horizontal shift of the camera's vessel, x and y (m)",
    "vessel_yaw_deg": "heading of the camera's vessel, added to the scenario's yaw (deg)",
    "camera_height_m": "camera height jitter along the vessel's z axis (m)",
    "camera_pitch_deg": "camera pitch jitter (deg, positive looks down)",
}
Pair = Annotated[tuple[float, float], Field(min_length=2, max_length=2)]


class Uniform(Section):
    uniform: Pair


class Normal(Section):
    normal: Pair
    clip: Pair | None = None


class Choice(Section):
    choice: Annotated[tuple[Any, ...], Field(min_length=1)]


Value = bool | int | float | str | tuple[float, ...] | Uniform | Normal | Choice


class Randomization(Section):
    version: Literal[1] = 1
    per: Literal["frame", "episode"] = "frame"
    frames_per_episode: Annotated[int, Field(ge=1)] = 1
    look: dict[str, Value] = {}
    scene: dict[Literal[tuple(SCENE)], Value] = {}  # type: ignore[valid-type]
    environment: dict[str, Value] = {}


def draw(value: Value, rng: np.random.Generator):
    """One sample of a constant or distribution (plain Python types, so that it round-trips through JSON)."""
    if isinstance(value, Uniform):
        return float(rng.uniform(*value.uniform))
    if isinstance(value, Normal):
        x = float(rng.normal(*value.normal))
        return float(np.clip(x, *value.clip)) if value.clip else x
    if isinstance(value, Choice):
        return value.choice[int(rng.integers(len(value.choice)))]
    return value


def draw_all(section: dict[str, Value], rng: np.random.Generator) -> dict[str, Any]:
    return {key: draw(section[key], rng) for key in sorted(section)}


def nested(flat: dict[str, Any]) -> dict[str, Any]:
    """{'sun.azimuth_deg': 3} → {'sun': {'azimuth_deg': 3}}."""
    out: dict[str, Any] = {}
    for path, value in flat.items():
        node = out
        *parents, leaf = path.split(".")
        for p in parents:
            node = node.setdefault(p, {})
        node[leaf] = value
    return out


def preset_names() -> list[str]:
    return sorted(
        p.name[:-5] for p in resources.files("usvsim.datasets.presets").iterdir() if p.name.endswith(".yaml")
    )


def load_randomization(name_or_path: str | Path | None) -> Randomization:
    """A preset by name (`clear_calm`, `foggy_wavy`) or a YAML file; None: nothing randomized."""
    if name_or_path is None:
        return Randomization()
    if str(name_or_path) in preset_names():
        source = resources.files("usvsim.datasets.presets").joinpath(f"{name_or_path}.yaml")
    else:
        source = Path(name_or_path)
        if not source.is_file():
            raise UsvsimError(
                f"randomization '{name_or_path}': no such file or preset (presets: {', '.join(preset_names())})"
            )
    try:
        data = yaml.safe_load(source.read_text())
        return Randomization.model_validate(data, strict=False)
    except (yaml.YAMLError, ValidationError) as exc:
        raise UsvsimError(f"randomization {name_or_path}: {_first_error(exc)}") from None


def _first_error(exc: Exception) -> str:
    if isinstance(exc, ValidationError):
        err = exc.errors()[0]
        return f"{'.'.join(str(p) for p in err['loc'])}: {err['msg']}"
    return str(exc).splitlines()[0]
