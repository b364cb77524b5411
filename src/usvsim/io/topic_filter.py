"""Which topics a recording keeps: exact names or shell-style patterns (`/tf*`, `/wamv/camera/*`; `*` matches
across `/`), and exclusions starting with `!` (`!/wamv/camera/*`: everything but the cameras), as
`usvsim run --record-topics`, `outputs.recording.topics` and `Simulation.record(topics=...)` take them. A topic
is kept when it matches one of the names (or there are only exclusions) and none of the exclusions.

A name that cannot match (no leading `/`: every topic the simulation emits is absolute) is a UsvsimError at
once; a name that matched no message while recording is reported by `unmatched()` with a "did you mean"
from the topics seen (it recorded nothing, in silence: `topics=["/wamv/imu"]` for `/wamv/imu/data`).
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable
from fnmatch import fnmatchcase

from usvsim.core.errors import UsvsimError


class TopicFilter:
    """`filter(topic)` is True for a topic to record; `None` patterns keep every topic."""

    def __init__(self, patterns: Iterable[str] | str | None, option: str = "topics") -> None:
        self.option = option
        self.patterns = None if patterns is None else _checked(patterns, option)
        self._include = [p for p in self.patterns or () if not p.startswith("!")]
        self._exclude = [p[1:] for p in self.patterns or () if p.startswith("!")]
        self._matched: set[str] = set()
        self._keep: dict[str, bool] = {}  # decided once per topic

    @property
    def seen(self) -> list[str]:
        """Every topic offered so far, kept or not."""
        return sorted(self._keep)

    def __call__(self, topic: str) -> bool:
        keep = self._keep.get(topic)
        if keep is None:
            included = [p for p in self._include if fnmatchcase(topic, p)]
            excluded = ["!" + p for p in self._exclude if fnmatchcase(topic, p)]
            self._matched.update(included + excluded)
            keep = self._keep[topic] = (bool(included) or not self._include) and not excluded
        return keep

    def unmatched(self) -> list[str]:
        """One line per name or exclusion that matched no topic offered so far, with the nearest topic seen."""
        lines = []
        for p in self.patterns or ():
            if p not in self._matched:
                near = difflib.get_close_matches(p.removeprefix("!"), self.seen, n=1, cutoff=0.6)
                hint = f" (did you mean {near[0]}?)" if near else ""
                lines.append(f"{self.option}: no message on {p.removeprefix('!')}{hint}")
        return lines


def _checked(patterns: Iterable[str] | str, option: str) -> tuple[str, ...]:
    items = [patterns] if isinstance(patterns, str) else patterns  # one name: not its characters
    items = list(items) if isinstance(items, Iterable) else [items]  # read once (a generator)
    if not all(isinstance(p, str) for p in items):
        raise UsvsimError(f"{option} is a topic name or names, not {patterns!r}")
    if not items:  # a recording of nothing
        raise UsvsimError(
            f"{option}: no topic given; name at least one (e.g. /clock) or leave it out for all"
        )
    for p in items:
        if not p.removeprefix("!").startswith("/"):
            raise UsvsimError(
                f"{option}: {p!r} is not a topic name: topics start with '/' (e.g. '/{p}', or '!/{p}' to leave it out)"
            )
    return tuple(dict.fromkeys(items))
