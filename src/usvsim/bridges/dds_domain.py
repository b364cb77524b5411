"""Cyclone DDS domains configured in code, shared by the bridges of one process.

Cyclone keeps one configured domain per domain id and process; creating it twice fails. Bridges acquire
it here (creating it with their configuration on first use) and release it on close; the last release
deletes it, so a later bridge can configure the domain afresh. The state is the process's, as Cyclone's is.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from typing import Any

_lock = threading.Lock()
_domains: dict[int, _Domain] = {}


@dataclass
class _Domain:
    domain_id: int
    config: str
    entity: Any  # cyclonedds.domain.Domain
    users: int = 0


def acquire_domain(domain_id: int, config: str) -> _Domain:
    """The configured domain `domain_id`; raises if it is already in use with another configuration."""
    from cyclonedds.domain import Domain

    with _lock:
        domain = _domains.get(domain_id)
        if domain is None:
            domain = _domains[domain_id] = _Domain(domain_id, config, Domain(domain_id, config))
        elif domain.config != config:
            raise RuntimeError(
                f"DDS domain {domain_id} is already open in this process with another configuration; "
                "close the other bridge first or use the same interface/config"
            )
        domain.users += 1
        return domain


def release_domain(domain: _Domain) -> None:
    """Drop one use of `domain`; the last one deletes it."""
    from usvsim.bridges.dds_types import delete_entity

    with _lock:
        domain.users -= 1
        if domain.users <= 0 and _domains.get(domain.domain_id) is domain:
            del _domains[domain.domain_id]
            delete_entity(domain.entity)
