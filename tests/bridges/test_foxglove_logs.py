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
