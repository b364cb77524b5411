"""PLACEHOLDER until the ocean work lands: flat sea only."""

from __future__ import annotations

from usvsim.config.base import Section


class Environment(Section):
    pass
