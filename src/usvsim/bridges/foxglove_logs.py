"""Foxglove SDK log records about clients, made safe: never more than a short excerpt of what a client sent,
and at most a few lines per client and minute (a client flooding invalid frames cannot flood the log)."""

from __future__ import annotations

import logging
import re
import time

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


def install() -> None:
    logger = logging.getLogger(CLIENT_LOGGER)
    if not any(isinstance(f, ClientLogLimiter) for f in logger.filters):
        logger.addFilter(ClientLogLimiter())
