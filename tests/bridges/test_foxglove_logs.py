"""The Foxglove SDK's log lines about clients: short excerpts, a few per client and minute."""

from __future__ import annotations

import logging

from usvsim.bridges.foxglove_logs import EXCERPT_CHARS, PER_MINUTE, ClientLogLimiter


def record(text: str) -> logging.LogRecord:
    return logging.LogRecord("foxglove.websocket.connected_client", logging.ERROR, __file__, 1, "%s", (text,), None)


def test_invalid_client_frames_are_cut_short_and_rate_limited_per_client():
    limiter = ClientLogLimiter()
    flood = [record(f"Invalid message from 127.0.0.1:4000{i % 2}: invalid type: string \"{'y' * 100_000}\"")
             for i in range(200)]  # fmt: skip
    passed = [r for r in flood if limiter.filter(r)]
    assert len(passed) == 2 * PER_MINUTE  # two clients, each limited on its own
    assert all(len(r.getMessage()) < EXCERPT_CHARS + 100 for r in passed)
    assert "suppressed" in passed[-1].getMessage()


class _Bridge:
    def __init__(self):
        self.stats = {"client_messages": 0, "client_refused": 0}

    def _count(self, key: str) -> None:
        self.stats[key] += 1


def test_messages_on_unknown_channels_count_into_the_only_open_bridge():
    """The SDK refuses them before any listener sees them and only logs it: they went uncounted. The record names no
    server, so with two bridges open in the process neither counts it (rather than the wrong one)."""
    from usvsim.bridges.foxglove_logs import UnknownChannels

    counter, one, two = UnknownChannels(), _Bridge(), _Bridge()
    counter.bridges.add(one)
    assert counter.filter(record("Received message for unknown channel: 9"))  # still logged (and limited)
    counter.filter(record("Client 127.0.0.1:40000 attempted to subscribe to unknown channel: 9"))  # not a message
    assert one.stats == {"client_messages": 1, "client_refused": 1}
    counter.filter(record("Invalid message from 127.0.0.1:40000: Unknown binary opcode 5"))  # refused: counted
    assert one.stats == {"client_messages": 2, "client_refused": 2}
    counter.bridges.add(two)
    counter.filter(record("Received message for unknown channel: 3"))
    assert one.stats["client_refused"] == 2 and two.stats["client_refused"] == 0
