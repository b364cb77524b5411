"""Reading scenario YAML defensively: size, encoding, nesting, aliases and expanded size are bounded
before the schema sees the data, and nothing of the input is echoed beyond a short excerpt.

Limits (docs/limits.md): a file of at most 4 MiB of UTF-8 text, nesting at most 64 levels, at most 256
aliases, at most 200,000 values once aliases are expanded (an "alias bomb" of nine levels of nine
aliases expands to 387 M values and is refused here, before anything walks it).
"""

from __future__ import annotations

import re
from pathlib import Path

import yaml

from usvsim.core.errors import ScenarioError

MAX_FILE_BYTES = 4 << 20
MAX_DEPTH = 64
MAX_ALIASES = 256
MAX_VALUES = 200_000
EXCERPT_CHARS = 60


_Base: type[yaml.SafeLoader] = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


class _Loader(_Base):
    """The safe loader, reading numbers as YAML 1.2 does: PyYAML (YAML 1.1) takes `1e9` or `5e-2` (an exponent
    without a decimal point) for the text '1e9', which the schema then refuses as "not a valid number".
    A key given twice in one mapping is an error (YAML requires unique keys; PyYAML silently keeps the last, so
    a second `vessels:` or `sensors:` would drop the first); keys over a merge (`<<: *base`) are overrides."""

    def construct_mapping(self, node, deep=False):
        if isinstance(node, yaml.MappingNode):
            seen: set = set()
            for key_node, _ in node.value:
                if key_node.tag == "tag:yaml.org,2002:merge" or not isinstance(key_node, yaml.ScalarNode):
                    continue
                key = self.construct_object(key_node)
                if key in seen:
                    raise yaml.constructor.ConstructorError(
                        None, None, f"key {excerpt(key)} is given twice in one mapping", key_node.start_mark
                    )
                seen.add(key)
        return super().construct_mapping(node, deep=deep)


Loader = _Loader  # for other YAML inputs of usvsim (sweep files): the same numbers and duplicate-key rule


_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?[0-9][0-9_]*(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789"),
)

# Booleans as YAML 1.2 (and the YAML language server checking a scenario against `usvsim schema`) read them: only
# true and false. PyYAML's YAML 1.1 also took yes/no/on/off, so `navigation: off` (a documented value) arrived as
# False and was refused as "should be 'auto', 'on' or 'off' (got False)", and `name: no` became False.
for _first in "yYnNoO":
    _Loader.yaml_implicit_resolvers[_first] = [
        (tag, regexp) for tag, regexp in _Loader.yaml_implicit_resolvers.get(_first, []) if tag != "tag:yaml.org,2002:bool"
    ]


def excerpt(value, limit: int = EXCERPT_CHARS) -> str:
    """repr() of a value cut to `limit` characters (a user's input is never echoed at length)."""
    text = repr(value) if not isinstance(value, (dict, list, tuple)) else _container_excerpt(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _container_excerpt(value) -> str:
    kind = type(value).__name__
    return f"<{kind} of {len(value)} item{'s' if len(value) != 1 else ''}>"


def read_text(path: Path, source: str) -> str:
    """The file's text; one-line errors for a missing, huge, binary or non-UTF-8 file."""
    try:
        with path.open("rb") as f:
            data = f.read(MAX_FILE_BYTES + 1)
    except OSError as exc:
        raise ScenarioError(source, "", f"cannot read the file: {exc.strerror or exc}") from None
    if len(data) > MAX_FILE_BYTES:
        raise ScenarioError(source, "", f"file larger than {MAX_FILE_BYTES >> 20} MiB; is it a scenario?")
    return decode(data, source)


def decode(data: bytes, source: str) -> str:
    nul = data.find(b"\0")
    if nul >= 0:
        raise ScenarioError(source, "", f"binary data (a NUL byte at offset {nul}); a scenario is YAML text")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ScenarioError(
            source, "", f"not UTF-8 text (invalid byte at offset {exc.start}); save it as UTF-8"
        ) from None


def parse(text: str, source: str):
    """YAML → plain data (safe loader), after checking nesting depth and alias count on the event stream."""
    try:
        _check_events(text, source)
        data = yaml.load(text, Loader=_Loader)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"line {mark.line + 1}" if mark else ""
        problem = str(getattr(exc, "problem", None) or "syntax error")
        raise ScenarioError(source, where, f"not valid YAML: {problem[:120]}") from None
    if data is None:
        raise ScenarioError(source, "", "empty scenario; a scenario starts with 'version: 1'")
    _check_values(data, source)
    return data


def _check_events(text: str, source: str) -> None:
    depth = aliases = 0
    for event in yaml.parse(text, Loader=_Loader):
        if isinstance(event, yaml.CollectionStartEvent):
            depth += 1
            if depth > MAX_DEPTH:
                line = event.start_mark.line + 1 if event.start_mark else "?"
                raise ScenarioError(source, f"line {line}", f"nested more than {MAX_DEPTH} levels deep")
        elif isinstance(event, yaml.CollectionEndEvent):
            depth -= 1
        elif isinstance(event, yaml.AliasEvent):
            aliases += 1
            if aliases > MAX_ALIASES:
                raise ScenarioError(source, "", f"more than {MAX_ALIASES} YAML aliases (*name)")


def _check_values(data, source: str) -> None:
    """Count values with aliases expanded (iteratively, stopping at the limit) and refuse control
    characters in strings (tabs and newlines excepted) and non-string mapping keys."""
    stack, count = [data], 0
    while stack:
        node = stack.pop()
        count += 1
        if count > MAX_VALUES:
            raise ScenarioError(source, "", f"more than {MAX_VALUES} values once aliases are expanded")
        if isinstance(node, dict):
            for key in node:
                if not isinstance(key, str):
                    raise ScenarioError(source, "", f"mapping key {excerpt(key)} is not a string")
                _check_string(key, source)
            stack.extend(node.values())
        elif isinstance(node, list):
            stack.extend(node)
        elif isinstance(node, str):
            _check_string(node, source)


def _check_string(text: str, source: str) -> None:
    bad = next((c for c in text if (ord(c) < 32 and c not in "\t\n\r") or 0x7F <= ord(c) < 0xA0), None)
    if bad is not None:
        raise ScenarioError(source, "", f"control character U+{ord(bad):04X} in the text {excerpt(text)}")
