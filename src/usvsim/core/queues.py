"""The bounded drop-oldest queue every bridge puts between the simulation and its I/O (design.md: bridges
never block the loop). A `deque(maxlen=...)` evicts its oldest item inside `append`, atomically, so a
producer and a consumer thread need no lock between them for the queue itself."""

from __future__ import annotations

from collections import deque
from typing import Any


def bounded(limit: int) -> deque:
    """An empty queue holding at most `limit` items."""
    return deque(maxlen=limit)


def push(queue: deque, item: Any) -> bool:
    """Append `item`; True when that pushed the oldest item out (count it as dropped)."""
    full = len(queue) == queue.maxlen
    queue.append(item)
    return full
