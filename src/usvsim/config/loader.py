"""Loading scenarios: built-in names or YAML files, validated with errors that name file and key path."""

from __future__ import annotations

import difflib
from importlib import resources
from pathlib import Path

import yaml
from pydantic import ValidationError

from usvsim.config import safe_yaml
from usvsim.config.base import KeyedValueError
from usvsim.config.scenario import Scenario
from usvsim.config.sensors import FRAME_PATTERN, TOPIC_FILTER_PATTERN, TOPIC_PATTERN
from usvsim.core.clock import latency_steps, period_ns, steps_per_period
from usvsim.core.errors import ScenarioError

BUILTIN_PACKAGE = "usvsim.scenarios"


def builtin_scenarios() -> dict[str, str]:
    """Built-in scenario names → one-line descriptions."""
    out = {}
    for entry in sorted(resources.files(BUILTIN_PACKAGE).iterdir(), key=lambda p: p.name):
        if entry.name.endswith(".yaml"):
            data = yaml.safe_load(entry.read_text()) or {}
            out[entry.name[: -len(".yaml")]] = str(data.get("description", "")).strip().splitlines()[0:1]
    return {k: (v[0] if v else "") for k, v in out.items()}


def resolve(name_or_path: str | Path) -> tuple[str, Path | None]:
    """(YAML text, base directory for relative paths) of a built-in name or a file path."""
    path = Path(name_or_path)
    if path.suffix in (".yaml", ".yml") or path.exists():
        if not path.is_file():
            what = "a directory, not a scenario file" if path.is_dir() else "no such scenario file"
            raise ScenarioError(str(path), "", what)
        return safe_yaml.read_text(path, str(path)), path.parent.resolve()
    entry = resources.files(BUILTIN_PACKAGE) / f"{name_or_path}.yaml"
    if len(str(name_or_path)) > 100 or not entry.is_file():
        names = list(builtin_scenarios())
        close = difflib.get_close_matches(str(name_or_path), names, n=1, cutoff=0.6)
        hint = f"did you mean {close[0]!r}? " if close else ""
        imazu = [n for n in names if n.startswith("imazu_")]  # 22 numbered cases: one range, not 22 names
        known = [n for n in names if n not in imazu] + ([f"{imazu[0]} .. {imazu[-1]}"] if imazu else [])
        name = safe_yaml.excerpt(str(name_or_path))
        raise ScenarioError(name, "", f"not a file and not a built-in scenario ({hint}built-ins: {', '.join(known)})")
    return entry.read_text(), Path(str(resources.files(BUILTIN_PACKAGE)))  # built-ins' files sit beside them


def load_scenario(name_or_path: str | Path) -> Scenario:
    """Parse and validate a scenario; raises ScenarioError naming the file and the key path."""
    text, base_dir = resolve(name_or_path)
    source = str(name_or_path)
    return parse_scenario(safe_yaml.parse(text, source), source, base_dir)


def parse_scenario(data, source: str = "<scenario>", base_dir: Path | None = None) -> Scenario:
    if not isinstance(data, dict):
        raise ScenarioError(source, "", "a scenario must be a mapping with at least 'version: 1'")
    if "version" not in data:
        raise ScenarioError(source, "version", "missing; add 'version: 1' at the top of the file")
    try:
        scenario = Scenario.model_validate(data)
    except ValidationError as exc:
        raise _first_error(exc, source, data) from None
    _check_rates(scenario, source)
    object.__setattr__(scenario, "_base_dir", base_dir)
    object.__setattr__(scenario, "_source", source)
    return scenario


def base_dir(scenario: Scenario) -> Path:
    """Directory that relative file paths in the scenario are resolved against."""
    return getattr(scenario, "_base_dir", None) or Path.cwd()


def source_of(scenario: Scenario) -> str:
    """The file or name the scenario came from, for error messages."""
    return getattr(scenario, "_source", None) or scenario.name


def first_error_text(exc: ValidationError, data, keys: list[str]) -> str:
    """A pydantic error of a section given as the mapping `data` (whose keys may be `keys`) as one line, "key: what
    is wrong", in the words of a scenario error."""
    first = exc.errors()[0]
    if first["type"] == "extra_forbidden" and len(first["loc"]) == 1:  # (the scenario's keys are not this section's)
        from usvsim.config.schema import did_you_mean

        more = len(exc.errors()) - 1
        return f"{first['loc'][0]}: unknown key" + did_you_mean(str(first["loc"][0]), keys) + (f" (+{more} more)" if more else "")
    err = _first_error(exc, "", data, whole_scenario=False)
    return f"{err.key_path}: {err.message}" if err.key_path else err.message


def _first_error(exc: ValidationError, source: str, data, whole_scenario: bool = True) -> ScenarioError:
    """The first of pydantic's errors as one line; `whole_scenario`: `data` is a scenario file's (not a section's),
    so its schema gives a bound error's allowed range."""
    err, counted = exc.errors()[0], len(exc.errors())
    counted -= sum(1 for e in exc.errors() if e["type"] == "too_short" and any(  # pydantic's echo of a bad item: a
        len(o["loc"]) > len(e["loc"]) and o["loc"][: len(e["loc"])] == e["loc"] for o in exc.errors()))  # shorter list
    if err["type"] == "missing":  # a required key missing beside an unknown key close to it: its misspelling, so
        # the line names the unknown key with its "did you mean" (it said "position: missing (+1 more error)")
        parent, wanted = tuple(err["loc"][:-1]), [str(err["loc"][-1])]
        err = next((e for e in exc.errors() if e["type"] == "extra_forbidden" and tuple(e["loc"][:-1]) == parent
                    and difflib.get_close_matches(str(e["loc"][-1]), wanted, n=1, cutoff=0.6)), err)  # fmt: skip
    loc = _readable_path(err["loc"], data)
    msg = err["msg"].removeprefix("Value error, ")  # our own validators' messages stand alone
    keyed = err.get("ctx", {}).get("error")
    if isinstance(keyed, KeyedValueError):  # a section's check about one key inside it: point at that key
        loc = f"{loc}{'' if keyed.key.startswith('[') or not loc else '.'}{keyed.key}"
    if err["type"] == "extra_forbidden":
        from usvsim.config.schema import allowed_keys, belongs_under, did_you_mean

        msg = "unknown key" + (belongs_under(err["loc"], data) or did_you_mean(str(err["loc"][-1]), allowed_keys(err["loc"], data)))
    elif err["type"] == "union_tag_not_found":  # was "Unable to extract tag using discriminator 'type'"
        from usvsim.config.schema import union_tags

        key, tags = union_tags(err["loc"], data)
        loc = f"{loc}.{key}" if loc else key
        named = err["input"].get("name") if isinstance(err["input"], dict) else None
        entry = f" (the entry named {safe_yaml.excerpt(named)})" if isinstance(named, str) else ""
        msg = f"missing{entry}; give one of: {', '.join(tags)}" if tags else f"missing{entry}"
    elif err["type"] == "union_tag_invalid":  # the key holding the tag: `type`, or `method` of a realization
        ctx = err.get("ctx", {})
        key = next((k for k, v in err["input"].items() if v == ctx.get("tag")), "type")
        msg = f"unknown {key} {safe_yaml.excerpt(ctx.get('tag'))}; expected one of {ctx.get('expected_tags')}"
    elif err["type"] == "missing" and err["loc"] and isinstance(err["loc"][-1], int):  # a list of fixed length too short
        given = _value_at(data, err["loc"][:-1])  # was "position[2]: missing, and required here"
        size = f", got {len(given)}" if isinstance(given, list) else ""
        loc = _readable_path(err["loc"][:-1], data)
        missing = [i for e in exc.errors() if e["type"] == "missing" and e["loc"][:-1] == err["loc"][:-1]
                   and isinstance(i := e["loc"][-1], int)]  # fmt: skip
        msg = f"should have {max(missing) + 1} items{size}"  # pydantic reports each missing item of the tuple
        counted -= len(missing) - 1
    elif err["type"] == "missing":  # pydantic: "Field required"
        msg = "missing, and required here (docs/scenario-reference.md)"
    elif err["type"] in YAML_SHAPES:  # pydantic said "Input should be a valid tuple" of a YAML list
        msg = f"should be {YAML_SHAPES[err['type']]}, got {_yaml_kind(err['input'])}"
    elif err["type"] == "string_pattern_mismatch":  # was "String should match pattern '^[A-Za-z]...'"
        pattern = err.get("ctx", {}).get("pattern", "")
        msg = f"{PATTERN_WORDS.get(pattern, msg)} (got {safe_yaml.excerpt(err['input'])})"
    elif err["type"] in ("too_short", "too_long"):  # was "Tuple should have at least 2 items after validation, not 1"
        ctx = err.get("ctx", {})
        bound = f"at least {ctx.get('min_length')}" if err["type"] == "too_short" else f"at most {ctx.get('max_length')}"
        bound = str(_fixed_length((*err["loc"], 0), data) or bound)  # a position: "should have 3 items, got 4"
        msg = f"should have {bound} items, got {ctx.get('actual_length')}"
    elif err["type"] == "bool_type" and isinstance(err["input"], str):  # yes/no/on/off: text in YAML 1.2
        msg = f"should be true or false (got the text {safe_yaml.excerpt(err['input'])})"
    elif err["type"] in BOUNDS:  # "Input should be >= 0.001" named neither the value nor the other end of the range
        from usvsim.config.schema import bounds_at

        allowed = bounds_at(err["loc"], data) if whole_scenario else ""
        msg = f"{msg} (got {safe_yaml.excerpt(err['input'])}{f'; allowed: {allowed}' if allowed else ''})"
    elif err["type"].endswith("_type") or err["type"] in ("literal_error", "finite_number"):
        msg = f"{msg} (got {safe_yaml.excerpt(err['input'])})"
    more = counted - 1
    if more:
        msg += f" (+{more} more error{'s' if more > 1 else ''})"
    return ScenarioError(source, loc, msg)


def _value_at(data, loc):
    """The value at pydantic location `loc` in the YAML data (None where the path leaves it; union tags skipped)."""
    for item in loc:
        if isinstance(item, int) and isinstance(data, list) and item < len(data):
            data = data[item]
        elif isinstance(data, dict) and item in data:
            data = data[item]
        elif not isinstance(data, dict) or isinstance(item, int):
            return None
    return data


def _fixed_length(loc, data) -> int | None:
    """How many items the fixed-length list holding pydantic location `loc` takes (a position: 3)."""
    from usvsim.config.schema import list_node_at

    items = list_node_at(loc[:-1], data).get("prefixItems")
    return len(items) if items else None


BOUNDS = ("greater_than", "greater_than_equal", "less_than", "less_than_equal", "multiple_of")
PATTERN_WORDS = {  # the name and topic patterns of config/*.py, in words
    r"^[A-Za-z][A-Za-z0-9_]*$": "should start with a letter and hold only letters, digits and '_'",
    TOPIC_PATTERN: "should be a ROS 2 topic name: '/'-separated parts of letters, digits and '_', none starting with a digit",
    TOPIC_FILTER_PATTERN: "should be a topic name or pattern starting with '/' (e.g. '/clock' or '/tf*'), or '!/' to leave one out",
    FRAME_PATTERN: "should be a frame name: '/'-separated parts of letters, digits and '_', none starting with a digit",
}
MAPPING = "a mapping (key: value lines, or {key: value, ...})"
YAML_SHAPES = {"tuple_type": "a list ([a, b], or one '- ' line per item)", "list_type": "a list ([a, b], or one '- ' line per item)",
               "model_attributes_type": MAPPING, "model_type": MAPPING, "dict_type": MAPPING}  # fmt: skip


def _yaml_kind(value) -> str:
    """What a parsed YAML value is, in YAML's words."""
    if value is None:
        return "nothing (null)"
    if isinstance(value, dict):
        return f"a mapping of {', '.join(safe_yaml.excerpt(str(k), 30) for k in list(value)[:4])}"[:160]
    kind = ("a boolean" if isinstance(value, bool) else "a number" if isinstance(value, int | float) else
            "the text" if isinstance(value, str) else "a list" if isinstance(value, list | tuple) else "the value")  # fmt: skip
    return f"{kind} {safe_yaml.excerpt(value)}"


def _readable_path(loc, data) -> str:
    """Key path like `vessels[0].thrusters[1].position`, skipping pydantic's union-tag segments."""
    parts, node, branch_named = [], data, False
    for depth, item in enumerate(loc):
        if isinstance(item, int):
            parts.append(f"[{item}]")
            node = node[item] if isinstance(node, (list, tuple)) and item < len(node) else None
            branch_named = False
        elif isinstance(node, dict) and not branch_named and "type" in node and item == node.get("type"):
            branch_named = True  # the tagged-union branch name, right after the entry (before a key of the
            continue  # same name: an object of type mesh with a stray `mesh:` key was 'objects[0].mesh.file')
        elif isinstance(node, dict) and not branch_named and item not in node and depth < len(loc) - 1:
            branch_named = True  # a branch tag the entry does not spell out: a realization's `method`, `fft` when
            continue  # left out (was 'environment.sea.realization.fft.res'); only the last item can be a missing key
        elif isinstance(node, dict) and item in node:
            parts.append(("." if parts else "") + item)
            node, branch_named = node[item], False
        else:
            parts.append(("." if parts else "") + str(item))
            node = None
    return "".join(parts)


def _check_rates(scenario: Scenario, source: str) -> None:
    try:
        step = period_ns(scenario.world.physics_rate_hz)
    except ValueError as exc:
        raise ScenarioError(source, "world.physics_rate_hz", str(exc)) from None
    rates = [(f"outputs.recording.{key}", getattr(scenario.outputs.recording, key))
             for key in ("clock_rate_hz", "ground_truth_rate_hz")
             if getattr(scenario.outputs.recording, key) is not None]  # null: fitted to the step  # fmt: skip
    rates += [(f"vessels[{i}].controller.rate_hz", v.controller.rate_hz)
              for i, v in enumerate(scenario.vessels) if v.controller]  # fmt: skip
    rates += [(f"vessels[{i}].sensors[{k}].rate_hz", sensor.rate_hz)
              for i, v in enumerate(scenario.vessels) for k, sensor in enumerate(v.sensors)]  # fmt: skip
    rates.append(("traffic.awareness.rate_hz", scenario.traffic.awareness.rate_hz))
    if scenario.outputs.markers.bodies_rate_hz:  # null: fitted to the step; 0: off
        rates.append(("outputs.markers.bodies_rate_hz", scenario.outputs.markers.bodies_rate_hz))
    for key, rate in rates:
        try:
            steps_per_period(rate, step)
        except ValueError as exc:
            raise ScenarioError(source, key, str(exc)) from None
    for i, vessel in enumerate(scenario.vessels):
        for k, sensor in enumerate(vessel.sensors):
            try:
                latency_steps(sensor.latency_s, step)
            except ValueError as exc:
                raise ScenarioError(source, f"vessels[{i}].sensors[{k}].latency_s", str(exc)) from None
