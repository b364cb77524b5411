"""Foxglove SDK log records about clients, made safe: never more than a short excerpt of what a client sent,
and at most a few lines per client and minute (a client flooding invalid frames cannot flood the log).

The SDK drops a client's message on a channel the client never advertised before any listener sees it, and says
so only in this log ("Received message for unknown channel: 9"), and so it does with a text frame that is not a
valid JSON operation or a binary frame with an unknown opcode ("Invalid message from 127.0.0.1:40000: unknown
variant `frobnicate`...", "... Unknown binary opcode 5"); `UnknownChannels` counts those records into the
bridge's `client_messages` and `client_refused`, as every other refused client message is counted. The record
does not say which server it came from: with one Foxglove bridge in the process (`usvsim run`, `usvsim task`) it is
that bridge's; with several open at once it cannot be told whose, and none counts it."""

from __future__ import annotations

import logging
import re
import time
import weakref
from collections.abc import Callable
from typing import Any

CLIENT_LOGGER = "foxglove.websocket.connected_client"
EXCERPT_CHARS = 160
PER_MINUTE = 5
_CLIENT = re.compile(r"from (\S+?):? ")


class ClientLogLimiter(logging.Filter):
    """Cuts each record to EXCERPT_CHARS and lets PER_MINUTE records per client address through a minute."""

    def __init__(self, per_minute: int = PER_MINUTE):
        super().__init__()
        self._per_minute = per_minute
        self._window: dict[str, tuple[float, int]] = {}  # client → (window start, records in it)

    def filter(self, record: logging.LogRecord) -> bool:
        text = record.getMessage()
        match = _CLIENT.search(text)
        client = match.group(1) if match else "?"
        now = time.monotonic()
        start, count = self._window.get(client, (now, 0))
        if now - start > 60.0:
            start, count = now, 0
        self._window[client] = (start, count + 1)
        if len(self._window) > 1024:  # forget old clients: the limiter's own memory stays bounded
            self._window = {client: self._window[client]}
        if count >= self._per_minute:
            return False
        text = text if len(text) <= EXCERPT_CHARS else text[:EXCERPT_CHARS] + "..."
        if count + 1 == self._per_minute:
            text += " (further messages about this client suppressed for a minute)"
        record.msg, record.args = text, ()
        return True


UNKNOWN_CHANNEL = "Received message for unknown channel"
INVALID_MESSAGE = "Invalid message from "  # bad JSON, a missing or unknown "op", an unknown binary opcode
REFUSED_BY_SDK = (UNKNOWN_CHANNEL, INVALID_MESSAGE)


class UnknownChannels(logging.Filter):
    """Counts the SDK's records of client messages it refused (on an unknown channel, invalid) into the one open
    bridge (see above)."""

    def __init__(self) -> None:
        super().__init__()
        self.bridges: weakref.WeakSet[Any] = weakref.WeakSet()

    def filter(self, record: logging.LogRecord) -> bool:
        if record.getMessage().startswith(REFUSED_BY_SDK) and len(self.bridges) == 1:
            bridge = next(iter(self.bridges))
            bridge._count("client_messages")
            bridge._count("client_refused")
        return True  # counted, then limited like any other record about a client


def install(bridge: Any = None) -> Callable[[], None]:
    """Limit the SDK's records about clients; with `bridge`, count the client messages the SDK refused (unknown
    channel, invalid) until the returned function is called (at the bridge's close)."""
    logger = logging.getLogger(CLIENT_LOGGER)
    counter = next((f for f in logger.filters if isinstance(f, UnknownChannels)), None)
    if counter is None:  # first: a record the limiter drops is still counted
        counter = UnknownChannels()
        logger.filters.insert(0, counter)
    if not any(isinstance(f, ClientLogLimiter) for f in logger.filters):
        logger.addFilter(ClientLogLimiter())
    if bridge is None:
        return lambda: None
    counter.bridges.add(bridge)
    return lambda: counter.bridges.discard(bridge)
