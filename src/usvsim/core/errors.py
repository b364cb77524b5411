"""Errors raised by usvsim. A user's mistake is a `UsvsimError`; the CLI prints it in one line, exit 2."""

from __future__ import annotations

import math

MAX_MESSAGE_CHARS = 600  # an error names what is wrong; it never echoes the user's input at length


class UsvsimError(Exception):
    """Base class for errors a user can fix (bad scenario, missing file, bad command)."""


class ScenarioError(UsvsimError):
    """A scenario file is invalid. Names the file, the key path and what is wrong."""

    def __init__(self, source, key_path: str | None = None, message: str | None = None):
        if key_path is None and message is None:  # one argument: an error of this kind (or its text) made again, as a
            other = source  # process boundary does (pickle; Gymnasium's async vector env raises type(err)(err))
            source, key_path, message = ((other.source, other.key_path, other.message) if isinstance(other, ScenarioError)
                                         else ("", "", str(other)))  # fmt: skip
        source, key_path, message = str(source)[:200], str(key_path)[:200], str(message)[:MAX_MESSAGE_CHARS]
        self.source = source
        self.key_path = key_path
        self.message = message
        super().__init__(": ".join(part for part in (source, key_path, message) if part))

    def __reduce__(self):
        return type(self), (self.source, self.key_path, self.message)


class MeshError(UsvsimError):
    """A mesh file is missing, unreadable or unsuitable (for example not watertight)."""


class DivergenceError(UsvsimError):
    """The numerical state became non-finite. Names the body and the simulation time."""

    def __init__(self, body, time_s: float | None = None, detail: str = ""):
        if time_s is None:  # one argument: an error of this kind (or its text) made again across a process boundary
            other = body
            self.body, self.time_s, self.detail = ((other.body, other.time_s, other.detail)
                                                   if isinstance(other, DivergenceError) else (None, None, ""))  # fmt: skip
            super().__init__(str(other))
            return
        self.body = body
        self.time_s = time_s
        self.detail = detail
        super().__init__(f"simulation diverged: body '{body}' at t = {time_s:.3f} s {detail}".rstrip())

    def __reduce__(self):
        if self.time_s is None:
            return type(self), (str(self),)
        return type(self), (self.body, self.time_s, self.detail)


class InputError(UsvsimError, ValueError):
    """A bad value given to the Python API (a pose, a twist, a model section): `except UsvsimError` and
    `except ValueError` both catch it."""


def require_finite(owner: str, name: str, value, zero_ok: bool = False, note: str = "") -> None:
    """InputError unless `value` is a finite real number > 0 (>= 0 with `zero_ok`): a Python API field checked as the
    scenario keys are (a NaN gain froze a vessel or made NaN commands far from the cause). `note` follows the bound
    in the message."""
    from numbers import Real

    ok = isinstance(value, Real) and not isinstance(value, bool) and math.isfinite(value)
    if not ok or value < 0 or (value == 0 and not zero_ok):
        raise InputError(f"{owner}.{name} must be a finite number {'>= 0' if zero_ok else '> 0'}{note}, not {value!r}")


class UnknownNameError(UsvsimError, KeyError):
    """A name that is not there (a body, a vessel): a KeyError whose text reads as one plain line (KeyError's own
    text is the repr of its message, quotes and escapes included)."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


class Names(dict):
    """A dict of named things (vessels, bodies, thrusters, sensors, controllers) whose missing name is an
    UnknownNameError listing the names there are (a bare KeyError: 'nope' named none)."""

    def __init__(self, kind: str, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.kind = kind

    def __missing__(self, key):
        raise UnknownNameError(f"no {self.kind} named {key!r}; the {self.kind} names: {sorted(self)}")
