"""The scenario file's JSON Schema, its Markdown reference, and "did you mean" for unknown keys.

All three come from the pydantic models (config/*.py), so they cannot drift from what the loader accepts.
`usvsim schema` prints the JSON Schema (for the YAML language server: `# yaml-language-server:
$schema=scenario.schema.json` at the top of a scenario); `usvsim schema --reference` prints
docs/scenario-reference.md (a test keeps the file in sync).
"""

from __future__ import annotations

import difflib
import json
from functools import cache
from typing import Any

from usvsim.config.scenario import Scenario

UNITS = {"_m": "m", "_mps": "m/s", "_s": "s", "_hz": "Hz", "_deg": "deg", "_rad": "rad", "_kg": "kg",
         "_n": "N", "_pa": "Pa", "_m2": "m²", "_m3": "m³", "_kgpm3": "kg/m³", "_mps2": "m/s²",
         "_deg_s": "deg/s", "_rad_s": "rad/s", "_radps": "rad/s", "_1ps": "1/s", "_n_s": "N/s", "_m2ps": "m²/s",
         "_mm_h": "mm/h", "_db": "dB", "_px": "px", "_ms": "ms", "_ev": "EV"}  # fmt: skip


@cache
def scenario_schema() -> dict[str, Any]:
    """JSON Schema (draft 2020-12) of a scenario file."""
    schema = Scenario.model_json_schema()
    return {"$schema": "https://json-schema.org/draft/2020-12/schema", **schema, "title": "usvsim scenario"}


def schema_json() -> str:
    return json.dumps(scenario_schema(), indent=2) + "\n"


# -- did you mean ------------------------------------------------------------------------------------
def allowed_keys(loc: tuple, data: Any) -> list[str]:
    """The keys the section at pydantic error location `loc` (ending in the unknown key) accepts."""
    node, _ = _node_at(loc[:-1], data)
    return list(node.get("properties", {}))


GENERIC_KEYS = {"type", "name", "method", "enabled"}


def belongs_under(loc: tuple, data: Any) -> str:
    """' (it belongs under 'thrust': thrust.max_forward_n)' when the unknown key at pydantic error location `loc` is a key
    of a section one or two levels below the one it was written in ('' when it is none's): a key one level too
    high read "did you mean 'max_rate_n_s'?" for a thruster's max_forward_n, and only "allowed: ..." for a top-level
    `sensors` (QA)."""
    node, defs = _node_at(loc[:-1], data)
    key, found = str(loc[-1]), []
    if key in GENERIC_KEYS:  # in every other section: `type: wamv` on a vessel is not buoyancy.type
        return ""
    for name, child in node.get("properties", {}).items():
        for path, section in _sections(child, defs, name):
            if key in section.get("properties", {}):
                found.append(f"{path}.{key}")
            for name2, child2 in section.get("properties", {}).items():
                found += [f"{path}.{p2}.{key}" for p2, s2 in _sections(child2, defs, name2) if key in s2.get("properties", {})]
    if not found:
        return ""
    found = sorted(dict.fromkeys(found), key=lambda p: (p.count("."), p))
    return f" (it belongs under '{found[0].split('.')[0].removesuffix('[]')}': {found[0]})"


def _sections(prop: dict, defs: dict, name: str) -> list[tuple[str, dict]]:
    """The object schemas a property can hold (through refs, unions and lists), with the path that reaches them."""
    prop = _resolve(prop, defs)
    if prop.get("type") == "array" and isinstance(prop.get("items"), dict):
        return _sections(prop["items"], defs, f"{name}[]")
    out = [(name, prop)] if "properties" in prop else []
    for option in prop.get("anyOf", []) + prop.get("oneOf", []):
        out += [(p, s) for p, s in _sections(option, defs, name) if (p, s) not in out]
    return out


def list_node_at(loc: tuple, data: Any) -> dict:
    """The array schema at pydantic error location `loc` (the list branch of an optional list); {} if none."""
    node, defs = _node_at(loc, data, resolve_last=True)
    for option in [node, *(_resolve(o, defs) for o in node.get("anyOf", []))]:
        if option.get("type") == "array":
            return option
    return {}


def union_tags(loc: tuple, data: Any) -> tuple[str, list[str]]:
    """The tag key (`type`, ...) and the accepted tags of the tagged union at pydantic error location `loc`."""
    node, defs = _node_at(loc, data, resolve_last=True)
    for option in [node, *(_resolve(o, defs) for o in node.get("anyOf", []))]:  # `X | None`: the union inside
        if "discriminator" in option:
            return option["discriminator"]["propertyName"], list(option["discriminator"].get("mapping", {}))
    return "type", []


def _node_at(loc: tuple, data: Any, resolve_last: bool = False) -> tuple[dict, dict]:
    """(the schema node at pydantic error location `loc`, the schema's definitions): at each step the tagged-union
    branch that `data` there takes; `resolve_last`: the last step's node itself (a union stays a union)."""
    defs = scenario_schema()["$defs"]
    node, value = _branch(scenario_schema(), data, defs), data
    for depth, item in enumerate(loc):
        if isinstance(item, int):
            node = node.get("items", {})
            value = value[item] if isinstance(value, list | tuple) and item < len(value) else None
        elif item in node.get("properties", {}):
            node = node["properties"][item]
            value = value.get(item) if isinstance(value, dict) else None
        else:
            continue  # pydantic's name of a tagged-union branch: `_branch` chose it already
        node = _resolve(node, defs) if resolve_last and depth == len(loc) - 1 else _branch(node, value, defs)
    return node, defs


def bounds_at(loc: tuple, data: Any) -> str:
    """The allowed range of the number at pydantic error location `loc`, e.g. '≥ 0, ≤ 100' ('' if the schema gives
    none there): a bound error named only the bound it broke."""
    node, defs = _node_at(loc, data, resolve_last=True)
    if loc and isinstance(loc[-1], int) and loc[-1] < len(items := list_node_at(loc[:-1], data).get("prefixItems", ())):
        node = _resolve(items[loc[-1]], defs)  # an item of a fixed-length list (a position's x)
    options = [node, *(_resolve(o, defs) for o in node.get("anyOf", ()))]
    return ", ".join(f"{sym} {_number(o[k])}" for o in options for k, sym in BOUND_SYMBOLS if k in o)


def _number(value: float) -> str:
    """100 for 100.0, 0.001 as is."""
    return str(int(value)) if float(value).is_integer() and abs(value) < 1e16 else repr(value)


def did_you_mean(key: str, allowed: list[str]) -> str:
    """' (did you mean 'x'?)' for a close match, else ' (allowed: a, b, ...)'; '' when nothing is allowed."""
    close = difflib.get_close_matches(key, allowed, n=1, cutoff=0.6)
    if close:
        return f" (did you mean {close[0]!r}?)"
    return f" (allowed: {', '.join(allowed)})" if allowed else ""


def _resolve(node: dict, defs: dict) -> dict:
    while "$ref" in node:
        node = defs[node["$ref"].rsplit("/", 1)[-1]]
    return node


def _branch(node: dict, value: Any, defs: dict) -> dict:
    """The object schema that applies to `value`: refs resolved, a union's branch chosen by its tag."""
    node = _resolve(node, defs)
    options = node.get("oneOf") or node.get("anyOf")
    if not options:
        return node
    mapping = node.get("discriminator", {}).get("mapping", {})
    tag = value.get(node["discriminator"]["propertyName"]) if mapping and isinstance(value, dict) else None
    if tag in mapping:
        return _resolve({"$ref": mapping[tag]}, defs)
    for option in options:
        chosen = _branch(option, value, defs)
        if "properties" in chosen or "items" in chosen:
            return chosen
    return node


# -- Markdown reference --------------------------------------------------------------------------------
def reference_markdown() -> str:
    """docs/scenario-reference.md: every section, its keys, types, units, defaults, allowed values."""
    schema = scenario_schema()
    defs = schema["$defs"]
    lines = ["# Scenario reference", "",
             "Generated from the scenario models by `usvsim schema --reference`; do not edit by hand (a test",
             "keeps it in sync). Units follow the key's suffix (`_m` metres, `_deg` degrees, `_hz` hertz, ...).",
             "Unknown keys are errors, with a suggestion for a likely misspelling. `usvsim schema` prints the",
             "JSON Schema for editor completion.", "",
             "Frames: world positions are ENU (x east, y north, z up) from `world.origin`; parts of a vessel (sensor",
             "mounts, thrusters, centre of mass) are in its `base_link` (FLU: x forward, y left, z up). Angles: `yaw_deg`",
             "is counter-clockwise from east (world) or from the bow (base_link); `heading_deg` and `course_deg` are",
             "compass angles, clockwise from north; the `direction` of waves, wind and current is where they travel",
             "toward. `[number, number, number]` is a list of exactly three.", ""]  # fmt: skip
    lines += _section("Scenario (top level)", schema, defs)
    for name in sorted(defs):
        if "properties" in defs[name]:
            lines += _section(name, defs[name], defs)
    return "\n".join(lines).rstrip() + "\n"


def _section(title: str, node: dict, defs: dict) -> list[str]:
    out = [f"## {title}", ""]
    if node.get("description") and title != "Scenario (top level)":
        out += [" ".join(node["description"].split()), ""]
    required = set(node.get("required", ()))
    out += ["| key | type | unit | default | description |", "|---|---|---|---|---|"]
    for key, prop in node["properties"].items():
        default = prop.get("default")
        default = "required" if key in required else "(its defaults)" if isinstance(default, dict) else f"`{_cell(json.dumps(default))}`"
        out.append(f"| `{key}` | {_type(prop, defs)} | {_unit(key)} | {default} | {_cell(_describe(prop))} |")
    return [*out, ""]


def _type(prop: dict, defs: dict) -> str:
    if "$ref" in prop:
        name = prop["$ref"].rsplit("/", 1)[-1]
        return f"[{name}](#{name.lower()})"
    if "const" in prop:
        return f"`{json.dumps(prop['const'])}`"
    if "enum" in prop:
        return " \\| ".join(f"`{json.dumps(v)}`" for v in prop["enum"])
    options = prop.get("oneOf") or prop.get("anyOf")
    if options:
        return " \\| ".join(_type(o, defs) for o in options)
    kind = prop.get("type", "any")
    if kind == "array" and "prefixItems" in prop:  # a fixed-length tuple (a position): was "list of number | number"
        return "[" + ", ".join(_type(item, defs) for item in prop["prefixItems"]) + "]"
    if kind == "array":
        return f"list of {_type(prop.get('items', {}), defs)}"
    if kind == "object" and "additionalProperties" in prop and isinstance(prop["additionalProperties"], dict):
        return f"map of {_type(prop['additionalProperties'], defs)}"
    return kind


BOUND_SYMBOLS = (("minimum", "≥"), ("exclusiveMinimum", ">"), ("maximum", "≤"), ("exclusiveMaximum", "<"))


def _describe(prop: dict) -> str:
    """The key's description and bounds; those of an optional value (`X | None`: inside its `anyOf`) and of a
    tuple's items ("each ...") too (an optional key's description was left out)."""
    options = [prop, *prop.get("anyOf", ())]
    texts = [" ".join(o["description"].split()) for o in options if o.get("description")]
    bounds = [f"{sym} {o[k]}" for o in options for k, sym in BOUND_SYMBOLS if k in o]
    items = [i for o in options for i in o.get("prefixItems", ())]
    item_bounds = [f"{sym} {items[0][k]}" for k, sym in BOUND_SYMBOLS if k in items[0]] if items else []
    if item_bounds and all(i == items[0] for i in items):
        bounds.append("each " + ", ".join(item_bounds))
    if "pattern" in prop:
        bounds.append(f"matches `{prop['pattern']}`")
    return "; ".join(part for part in ("; ".join(dict.fromkeys(texts)), ", ".join(bounds)) if part)


NO_UNIT = {"spreading_s", "c_n"}  # keys whose suffix is not a unit (cos-2s spreading's exponent s, a coefficient)
KEY_UNITS = {"direction": "rad", "direction_std": "rad", "phase": "rad", "angle": "rad", "rpm": "rev/min",
             "position": "m", "size": "m", "com": "m", "reference_point": "m", "inertia": "kg m²",
             "latlon": "deg"}  # keys without a unit suffix  # fmt: skip


def _unit(key: str) -> str:
    if key in NO_UNIT:
        return ""
    if key in KEY_UNITS:
        return KEY_UNITS[key]
    for suffix in sorted(UNITS, key=len, reverse=True):
        if key.endswith(suffix):
            return UNITS[suffix]
    return ""


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")
