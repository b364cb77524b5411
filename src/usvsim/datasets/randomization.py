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

import math
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
import yaml
from pydantic import Field, ValidationError, model_validator

from usvsim.config import safe_yaml
from usvsim.config.base import Section
from usvsim.config.safe_yaml import excerpt
from usvsim.core.errors import UsvsimError

SCENE = {  # scene parameters: what each one changes (added to the scenario's value)
    "buoy_offset_m": "horizontal shift of each buoy, x and y drawn separately (m)",
    "vessel_offset_m": "horizontal shift of each camera's vessel, x and y drawn separately (m)",
    "vessel_yaw_deg": "heading of each camera's vessel, added to the scenario's yaw (deg)",
    "camera_height_m": "camera height jitter along the vessel's z axis (m)",
    "camera_pitch_deg": "camera pitch jitter (deg, positive looks down)",
}
SCENE_BOUNDS = {  # what a scene value may be (a pitch of 200° turned the camera upside down; an offset of 1e7 m
    "buoy_offset_m": (-1000.0, 1000.0),  # made MuJoCo diverge; none was refused, qa20)
    "vessel_offset_m": (-1000.0, 1000.0),
    "vessel_yaw_deg": (-360.0, 360.0),  # a full turn either way: {uniform: [0, 360]} is any heading
    "camera_height_m": (-20.0, 20.0),
    "camera_pitch_deg": (-90.0, 90.0),
}
Pair = Annotated[tuple[float, float], Field(min_length=2, max_length=2)]


class Uniform(Section):
    uniform: Pair

    @model_validator(mode="after")
    def _ordered(self):
        if self.uniform[0] > self.uniform[1]:
            raise ValueError(f"uniform: low {self.uniform[0]:g} is above high {self.uniform[1]:g}")
        return self


class Normal(Section):
    normal: Pair
    clip: Pair | None = None

    @model_validator(mode="after")
    def _spread(self):
        if self.normal[1] < 0:
            raise ValueError(f"normal: the stddev {self.normal[1]:g} is negative")
        if self.clip is not None and self.clip[0] > self.clip[1]:
            raise ValueError(f"clip: low {self.clip[0]:g} is above high {self.clip[1]:g}")
        return self


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

    @model_validator(mode="after")
    def _scene_numbers(self):
        """Scene values are numbers added to the scenario's (a `choice: [a, b]` of strings was a numpy
        UFuncTypeError traceback at the first frame), within SCENE_BOUNDS at every end of their range (a normal
        without clip: its mean; its draws are checked by `check_scene`)."""
        for key, value in self.scene.items():
            for v in support_ends(value):
                if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                    raise ValueError(f"scene.{key}: {_shown(v)} is not a number ({SCENE[key]})")
                check_scene(key, v)
        return self


def check_scene(key: str, value: float) -> None:
    """A ValueError naming the scene key when `value` lies outside its SCENE_BOUNDS."""
    low, high = SCENE_BOUNDS[key]
    if not low <= value <= high:
        raise ValueError(f"scene.{key}: {value:g} is outside {low:g}..{high:g} ({SCENE[key]})")


def support_ends(value) -> tuple:
    """The values a distribution reaches at its ends (a normal without clip: its mean only)."""
    if isinstance(value, Uniform):
        return value.uniform
    if isinstance(value, Normal):
        return value.clip if value.clip else (value.normal[0],)
    if isinstance(value, Choice):
        return value.choice
    return (value,)


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
    where = f"randomization {name_or_path}"
    text = source.read_text() if not isinstance(source, Path) else safe_yaml.read_text(source, where)
    data = None
    try:
        data = yaml.safe_load(text)
        return Randomization.model_validate(data, strict=False)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = f"line {mark.line + 1}: " if mark is not None else ""
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise UsvsimError(f"{where}: {line}not valid YAML: {problem}") from None
    except ValidationError as exc:
        raise UsvsimError(f"{where}: {_first_error(exc, data)}") from None


FORMS = {"uniform": "{uniform: [low, high]}", "normal": "{normal: [mean, stddev]} (clip: [low, high] optional)",
         "choice": "{choice: [a, b, ...]} (at least one value)"}  # fmt: skip
SECTIONS = ("look", "scene", "environment")


def _shown(value) -> str:
    text = repr(value)
    return text if len(text) <= 80 else excerpt(value)


def _first_error(exc: ValidationError, data) -> str:
    """One line in the file's words (pydantic's named union branches, '[key]' and 'tuple[float, ...]')."""
    from usvsim.config.schema import did_you_mean

    errors = exc.errors()
    err, loc = errors[0], errors[0]["loc"]
    if not loc and err["type"] == "model_type":
        return f"a randomization file is a mapping of {', '.join(Randomization.model_fields)}; got {excerpt(data)}"
    if err["type"] == "extra_forbidden" and len(loc) == 1:
        return f"{loc[0]}: unknown key{did_you_mean(str(loc[0]), list(Randomization.model_fields))}"
    if len(loc) >= 3 and loc[0] in SECTIONS and loc[2] == "[key]":
        return f"{loc[0]}: unknown key {excerpt(loc[1])}{did_you_mean(str(loc[1]), list(SCENE))}"
    if len(loc) >= 3 and loc[0] in SECTIONS:  # a value: every branch of the union failed
        key, value = f"{loc[0]}.{loc[1]}", data[loc[0]][loc[1]]
        checked = next((e for e in errors if e["type"] == "value_error" and e["loc"][:2] == loc[:2]), None)
        if checked is not None:  # the distribution's form is right, its parameters are not
            return f"{key}: {checked.get('ctx', {}).get('error', checked['msg'])}"
        form = next((f for d, f in FORMS.items() if isinstance(value, dict) and d in value), None)
        if form is not None:
            return f"{key}: {_shown(value)} is not {form}"
        return f"{key}: {_shown(value)} is neither a constant nor one of {', '.join(FORMS.values())}"
    if not loc and err["type"] == "value_error":  # a check across the file (_scene_numbers)
        return str(err.get("ctx", {}).get("error", err["msg"]))
    return f"{'.'.join(str(p) for p in loc)}: {err['msg']}"
