"""Named random streams: one scenario seed, one independent `numpy.random.Generator` per subsystem.

Adding a stream never changes another stream's numbers: each stream's seed is derived from the
scenario seed and a hash of its name, not from the order in which streams are created.
"""

from __future__ import annotations

import hashlib

import numpy as np

from usvsim.core.errors import UsvsimError


class RngStreams:
    def __init__(self, seed: int):
        self.seed = _checked(seed)
        self._streams: dict[str, np.random.Generator] = {}  # what `get` returns
        self._handed: dict[str, np.random.Generator] = {}  # what `get` last returned: a holder keeps it

    def get(self, name: str) -> np.random.Generator:
        gen = self._streams.get(name)
        if gen is None:
            gen = self._streams[name] = self._fresh(name)
        self._handed[name] = gen
        return gen

    def reseed(self, seed: int) -> None:
        """Every stream back to its first number under `seed`, in place: the holder of a generator (the one `get`
        last returned for its name) keeps it and draws what a fresh `RngStreams(seed)` would give, at every reseed.
        (`get` after this returns a fresh generator, whose `spawn` children match a fresh run's; it reset the
        generator in the table instead of the holder's from the second reseed on: sensor noise then differed.)"""
        self.seed = _checked(seed)
        for name, held in self._handed.items():
            fresh = self._fresh(name)
            held.bit_generator.state = fresh.bit_generator.state
            self._streams[name] = fresh

    def _fresh(self, name: str) -> np.random.Generator:
        digest = hashlib.sha256(name.encode()).digest()
        key = [int.from_bytes(digest[i : i + 4], "little") for i in range(0, 16, 4)]
        return np.random.Generator(np.random.PCG64(np.random.SeedSequence([self.seed, *key])))


def _checked(seed: int) -> int:
    """numpy's SeedSequence takes non-negative integers only; say so in one line rather than in its ValueError."""
    try:
        ok = not isinstance(seed, bool) and int(seed) == seed and seed >= 0
    except (TypeError, ValueError, OverflowError):  # "a", None, nan, inf: not numbers or not integers
        ok = False
    if not ok:
        raise UsvsimError(f"a seed is a non-negative integer, got {seed!r}")
    return int(seed)
