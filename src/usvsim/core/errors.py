"""Errors raised by usvsim. A user's mistake is a `UsvsimError`; the CLI prints it in one line, exit 2."""

from __future__ import annotations

MAX_MESSAGE_CHARS = 600  # an error names what is wrong; it never echoes the user's input at length


class UsvsimError(Exception):
    """Base class for errors a user can fix (bad scenario, missing file, bad command)."""


class ScenarioError(UsvsimError):
    """A scenario file is invalid. Names the file, the key path and what is wrong."""

    def __init__(self, source: str, key_path: str, message: str):
        source, key_path, message = source[:200], key_path[:200], message[:MAX_MESSAGE_CHARS]
        self.source = source
        self.key_path = key_path
        self.message = message
        where = f"{source}: {key_path}: " if key_path else f"{source}: "
        super().__init__(where + message)


class MeshError(UsvsimError):
    """A mesh file is missing, unreadable or unsuitable (for example not watertight)."""


class DivergenceError(UsvsimError):
    """The numerical state became non-finite. Names the body and the simulation time."""

    def __init__(self, body: str, time_s: float, detail: str = ""):
        self.body = body
        self.time_s = time_s
        super().__init__(f"simulation diverged: body '{body}' at t = {time_s:.3f} s {detail}".rstrip())


class InputError(UsvsimError, ValueError):
    """A bad value given to the Python API (a pose, a twist, a model section): `except UsvsimError` and
    `except ValueError` both catch it."""


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
