"""Cyclone DDS domains configured in code, shared by the bridges of one process.

Cyclone keeps one configured domain per domain id and process; creating it twice fails. Bridges acquire
it here (creating it with their configuration on first use) and release it on close; the last release
deletes it, so a later bridge can configure the domain afresh. The state is the process's, as Cyclone's is.

Loopback pinning: Cyclone binds its UDP sockets to the wildcard address whatever interface it is told to use
(upstream eclipse-cyclonedds/cyclonedds#1923, #2090), so on a loopback-only configuration they would still
accept datagrams arriving on any interface. `acquire_domain(..., device="lo")` binds every wildcard UDP socket
the new domain opened to the loopback device (Linux `SO_BINDTODEVICE`, unprivileged since Linux 5.7): the
kernel then delivers them only what arrives on `lo`, and `ss -lunp` shows them as `0.0.0.0%lo`.
"""

from __future__ import annotations

import os
import socket
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


def acquire_domain(domain_id: int, config: str, device: str | None = None) -> _Domain:
    """The configured domain `domain_id`; raises if it is already in use with another configuration. A new
    domain's wildcard UDP sockets are bound to network `device` (e.g. "lo") when one is given."""
    from cyclonedds.domain import Domain

    with _lock:
        domain = _domains.get(domain_id)
        if domain is None:
            before = socket_fds()
            entity = Domain(domain_id, config)
            if device is not None:
                bind_to_device(socket_fds() - before, device)
            domain = _domains[domain_id] = _Domain(domain_id, config, entity)
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


def socket_fds() -> set[int]:
    fds = set()
    for name in os.listdir("/proc/self/fd") if os.path.isdir("/proc/self/fd") else ():
        try:
            if os.readlink(f"/proc/self/fd/{name}").startswith("socket:"):
                fds.add(int(name))
        except OSError:  # closed meanwhile
            continue
    return fds


def bind_to_device(fds: set[int], device: str) -> int:
    """Bind those of `fds` that are UDP sockets on a wildcard address to `device`; returns how many."""
    if not hasattr(socket, "SO_BINDTODEVICE"):
        return 0  # not Linux: the sockets stay as Cyclone made them
    pinned = 0
    for fd in sorted(fds):
        try:
            sock = socket.socket(fileno=fd)
        except OSError:
            continue
        try:
            wildcard = sock.getsockname()[0] in ("0.0.0.0", "::")
            if sock.type == socket.SOCK_DGRAM and sock.family in (socket.AF_INET, socket.AF_INET6) and wildcard:
                sock.setsockopt(socket.SOL_SOCKET, socket.SO_BINDTODEVICE, device.encode())
                pinned += 1
        finally:
            sock.detach()  # the descriptor stays Cyclone's
    return pinned
