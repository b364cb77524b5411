"""The Foxglove front proxy (foxglove_proxy.py) in a child process, so that its byte copying never holds the
simulation's GIL.

    proxy = ProxyProcess("127.0.0.1", 8765, upstream_port, max_clients=16, count=stats_counter)
    proxy.port, proxy.clients
    proxy.close()

The child (`python -m usvsim.bridges.foxglove_proxy_process HOST PORT UPSTREAM MAX_CLIENTS MAX_BUFFER STALL_S
HANDSHAKE_S`) writes one line per event on its stdout: `port N` once it listens (or `error TEXT` and exit 2),
`count KEY` for each counter increment, `clients N` when the number of served connections changes, and
`log TEXT` for each warning. It stops when its stdin reaches end of file: when `close()` closes it, or when the
simulation's process dies.
"""

from __future__ import annotations

import logging
import os
import subprocess
import sys
import threading
from collections.abc import Callable

from usvsim.bridges.foxglove_proxy import HANDSHAKE_S, FoxgloveProxy

log = logging.getLogger("usvsim.bridges.foxglove_proxy")
START_TIMEOUT_S = 30.0  # a cold interpreter on a loaded machine
CHILD_NICENESS = 10  # on a busy CPU the viewers' feed slows before the simulation does


class ProxyProcess:
    """`FoxgloveProxy` in a child process; the same constructor arguments, `port`, `clients` and `close()`."""

    def __init__(
        self,
        host: str,
        port: int,
        upstream_port: int,
        *,
        max_clients: int = 16,
        max_buffer_bytes: int = 16 << 20,
        stall_s: float = 10.0,
        handshake_s: float = HANDSHAKE_S,
        count: Callable[[str], None] = lambda key: None,
    ) -> None:
        if max_clients < 1 or max_buffer_bytes < 1:
            raise ValueError(
                f"max_clients and max_buffer_bytes must be >= 1, got {max_clients}, {max_buffer_bytes}"
            )
        args = [host, port, upstream_port, max_clients, max_buffer_bytes, stall_s, handshake_s]
        self._child = subprocess.Popen(
            [sys.executable, "-m", __name__, *map(str, args)],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, bufsize=1,
        )  # fmt: skip
        self._count, self.clients = count, 0
        first = _first_line(self._child, START_TIMEOUT_S)
        if not first.startswith("port "):
            self.close()
            raise OSError(first.removeprefix("error ") or "the Foxglove proxy process did not start")
        self.port = int(first.split()[1])
        self._reader = threading.Thread(target=self._read_events, name="foxglove-proxy-events", daemon=True)
        self._reader.start()

    def _read_events(self) -> None:
        assert self._child.stdout is not None
        for line in self._child.stdout:
            kind, _, rest = line.rstrip("\n").partition(" ")
            if kind == "count":
                self._count(rest)
            elif kind == "clients":
                self.clients = int(rest)
            elif kind == "log":
                log.warning("%s", rest)

    def close(self) -> None:
        """Stop the child (end of its stdin; killed if it does not exit within 5 s)."""
        child = self._child
        if child.poll() is None:
            try:
                child.stdin.close()  # type: ignore[union-attr]
                child.wait(timeout=5.0)
            except (OSError, subprocess.TimeoutExpired):
                child.kill()
                child.wait()


def _first_line(child: subprocess.Popen, timeout_s: float) -> str:
    box: list[str] = []
    reader = threading.Thread(target=lambda: box.append(child.stdout.readline()), daemon=True)  # type: ignore[union-attr]
    reader.start()
    reader.join(timeout_s)
    return box[0].strip() if box else ""


def _child_main(argv: list[str]) -> int:
    os.nice(CHILD_NICENESS)
    host, port, upstream, max_clients, max_buffer = argv[0], *map(int, argv[1:5])
    stall_s, handshake_s = map(float, argv[5:7])
    lock = threading.Lock()

    def emit(line: str) -> None:
        with lock:
            sys.stdout.write(line.replace("\n", " ") + "\n")
            sys.stdout.flush()

    class _Forward(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            emit("log " + record.getMessage())

    proxy_log = logging.getLogger("usvsim.bridges.foxglove_proxy")
    proxy_log.addHandler(_Forward())
    proxy_log.propagate = False
    try:
        proxy = FoxgloveProxy(host, port, upstream, max_clients=max_clients, max_buffer_bytes=max_buffer,
                              stall_s=stall_s, handshake_s=handshake_s, count=lambda k: emit(f"count {k}"),
                              on_clients=lambda n: emit(f"clients {n}"))  # fmt: skip
    except (OSError, ValueError) as exc:
        emit(f"error {str(exc)[:200]}")
        return 2
    emit(f"port {proxy.port}")
    sys.stdin.read()  # until the simulation closes our stdin or exits
    proxy.close()
    return 0


if __name__ == "__main__":
    sys.exit(_child_main(sys.argv[1:]))
