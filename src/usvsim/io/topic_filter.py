"""Which topics a recording keeps: exact names or shell-style patterns (`/tf*`, `/wamv/camera/*`), as
`usvsim run --record-topics` and `Simulation.record(topics=...)` take them.

A name that cannot match (no leading `/`: every topic the simulation emits is absolute) is a UsvsimError at
once; a pattern that matched no message while recording is reported by `unmatched()` with a "did you mean"
from the topics seen (it recorded nothing, in silence: `topics=["/wamv/imu"]` for `/wamv/imu/data`).
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable
from fnmatch import fnmatchcase

from usvsim.core.errors import UsvsimError

_GLOB = frozenset("*?[")


class TopicFilter:
    """`filter(topic)` is True for a topic to record; `None` patterns keep every topic."""

    def __init__(self, patterns: Iterable[str] | str | None, option: str = "topics") -> None:
        self.option = option
        if patterns is None:
            self.patterns: tuple[str, ...] | None = None
        else:
            items = [patterns] if isinstance(patterns, str) else patterns  # one name: not its characters
            items = list(items) if isinstance(items, Iterable) else [items]  # read once (a generator)
            if not all(isinstance(p, str) for p in items):
                raise UsvsimError(f"{option} is a topic name or names, not {patterns!r}")
            if not items:  # a recording of nothing
                raise UsvsimError(
                    f"{option}: no topic given; name at least one (e.g. /clock) or leave it out for all"
                )
            for p in items:
                if not p.startswith("/"):
                    raise UsvsimError(
                        f"{option}: {p!r} is not a topic name: topics start with '/' (e.g. '/{p}')"
                    )
            self.patterns = tuple(dict.fromkeys(items))
        self._exact = frozenset(p for p in self.patterns or () if not _GLOB & set(p))
        self._globs = tuple(p for p in self.patterns or () if _GLOB & set(p))
        self._matched: set[str] = set()
        self._keep: dict[str, bool] = {}  # decided once per topic

    @property
    def seen(self) -> list[str]:
        """Every topic offered so far, kept or not."""
        return sorted(self._keep)

    def __call__(self, topic: str) -> bool:
        keep = self._keep.get(topic)
        if keep is None:
            hits = [p for p in self._globs if fnmatchcase(topic, p)] + (
                [topic] if topic in self._exact else []
            )
            self._matched.update(hits)
            keep = self._keep[topic] = self.patterns is None or bool(hits)
        return keep

    def unmatched(self) -> list[str]:
        """One line per pattern that matched no topic offered so far, with the nearest topic seen."""
        lines = []
        for p in self.patterns or ():
            if p not in self._matched:
                near = difflib.get_close_matches(p, self.seen, n=1, cutoff=0.6)
                hint = f" (did you mean {near[0]}?)" if near else ""
                lines.append(f"{self.option}: no message on {p}{hint}")
        return lines
