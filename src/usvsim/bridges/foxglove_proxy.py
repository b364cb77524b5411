"""Connection limit in front of the Foxglove server: a TCP pump that owns the user-facing host:port.

foxglove-sdk 0.30 has no hook to refuse or drop a client, so the bridge binds the SDK server on an internal
loopback port and puts this proxy on the address users connect to. It runs an asyncio loop in one daemon
thread and, per connection, copies bytes both ways unchanged (the WebSocket handshake included):
- a connection must send its upgrade request within `handshake_s` (else it is closed and counted as dropped);
  at most `4 * max_clients` connections may be waiting for theirs, so idle sockets cannot take the slots;
- at most `max_clients` connections at once; one more gets `HTTP/1.1 503` to its upgrade request and is closed;
- server → client: while more than PAUSE_BYTES wait for a client, the proxy stops reading its server side,
  so the SDK's bounded per-client queue drops the oldest data (a slow client gets the newest, not everything);
  a client whose unsent bytes exceed `max_buffer_bytes`, or that takes nothing for `stall_s` seconds while
  paused (it stopped reading), is dropped: both of its connections are aborted, so the SDK forgets it too.
  Memory for clients is thus bounded by `max_clients * max_buffer_bytes`;
- client → server bytes wait for the server (backpressure to the client).
Counters go through `count(key)` (`connections_accepted`, `connections_refused`, `connections_dropped`);
refusals and drops are logged at most once per kind and 10 s, with the totals.

`foxglove_proxy_process.ProxyProcess` runs the same proxy in a child process (`python -m usvsim.bridges.foxglove_proxy_process`), which is what
the bridge uses: copying hundreds of MB/s through asyncio in the simulation's process would take the GIL from
the step loop. The child reports its port, counters, client count and log lines on its stdout, one line each,
and exits when its stdin closes (so it never outlives the simulation).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import threading
import time
from collections.abc import Callable

log = logging.getLogger(__name__)
REFUSAL_BODY = b"too many Foxglove clients\n"
REFUSAL = b"HTTP/1.1 503 Service Unavailable\r\nContent-Type: text/plain\r\nConnection: close\r\n" \
          b"Content-Length: %d\r\n\r\n%s" % (len(REFUSAL_BODY), REFUSAL_BODY)  # fmt: skip
READ_BYTES = 1 << 18
PAUSE_BYTES = 1 << 20  # a client this far behind pauses its server side (the SDK then drops its oldest data)
LOG_PERIOD_S = 10.0
CLOSE_TIMEOUT_S = 2.0  # how long a closing connection may take to flush its last bytes
CLOSE_GRACE_S = 2.0  # at close, how long connections may take to end on their own (the server's close frames;
# it returns as soon as they have: the margin is for a loaded machine)
HANDSHAKE_S = 5.0  # how long a new connection may take to send its WebSocket upgrade request
PENDING_PER_CLIENT = 4  # connections that may wait for their upgrade request, per client slot


class FoxgloveProxy:
    """Listens on host:port (port 0: a free one, see `port`) and forwards to 127.0.0.1:`upstream_port`."""

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
        on_clients: Callable[[int], None] = lambda n: None,
    ) -> None:
        if max_clients < 1 or max_buffer_bytes < 1:
            raise ValueError(
                f"max_clients and max_buffer_bytes must be >= 1, got {max_clients}, {max_buffer_bytes}"
            )
        self.max_clients, self.max_buffer_bytes, self.stall_s = max_clients, max_buffer_bytes, stall_s
        self.handshake_s = handshake_s
        self._upstream_port, self._count, self._on_clients = upstream_port, count, on_clients
        self._totals = {"connections_refused": 0, "connections_dropped": 0}
        self._last_log: dict[str, float] = {}
        self._clients: set[asyncio.Task] = set()
        self._pending: set[asyncio.Task] = set()  # connections waiting for their upgrade request
        self._loop = asyncio.new_event_loop()
        try:
            self._server = self._loop.run_until_complete(asyncio.start_server(self._serve, host, port))
        except BaseException:
            self._loop.close()
            raise
        self.port: int = self._server.sockets[0].getsockname()[1]
        self._thread = threading.Thread(target=self._loop.run_forever, name="foxglove-proxy", daemon=True)
        self._thread.start()

    @property
    def clients(self) -> int:
        """Connections being served now."""
        return len(self._clients)

    def close(self) -> None:
        """Stop listening, abort every connection, stop the loop thread."""
        if self._thread is None:
            return
        thread, self._thread = self._thread, None
        with contextlib.suppress(Exception):
            asyncio.run_coroutine_threadsafe(self._shutdown(), self._loop).result(timeout=5.0)
        self._loop.call_soon_threadsafe(self._loop.stop)
        thread.join(timeout=5.0)
        if not thread.is_alive():
            self._loop.close()

    async def _shutdown(self) -> None:
        self._server.close()
        if self._clients:  # the server stopped first: its close frames reach the clients
            await asyncio.wait(list(self._clients), timeout=CLOSE_GRACE_S)
        tasks = [*self._clients, *self._pending]
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)

    # -- loop thread ------------------------------------------------------------------------------
    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            request = await self._upgrade_request(reader)
            if request is None:
                return
            if len(self._clients) >= self.max_clients:
                return await self._refuse(writer)
            await self._forward(request, reader, writer)
        except asyncio.CancelledError:
            pass  # close(): asyncio's start_server callback would report a cancelled handler as an error
        finally:
            writer.transport.abort()

    async def _upgrade_request(self, reader: asyncio.StreamReader) -> bytes | None:
        """The client's HTTP upgrade request, or None (too many waiting, too slow, too long, or gone)."""
        if len(self._pending) >= PENDING_PER_CLIENT * self.max_clients:
            self._note("connections_refused", f"refused a client: {len(self._pending)} connections wait to start")
            return None
        task = asyncio.current_task()
        assert task is not None, "called from a coroutine"
        self._pending.add(task)
        try:
            return await asyncio.wait_for(reader.readuntil(b"\r\n\r\n"), self.handshake_s)
        except TimeoutError:
            self._note("connections_dropped", f"dropped a client: no upgrade request within {self.handshake_s} s")
        except (asyncio.IncompleteReadError, asyncio.LimitOverrunError, OSError):
            pass  # gone before its request, or a request longer than the stream limit (64 KiB)
        finally:
            self._pending.discard(task)
        return None

    async def _forward(self, request: bytes, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        task = asyncio.current_task()
        assert task is not None, "called from a coroutine"
        self._clients.add(task)
        self._on_clients(len(self._clients))
        up_writer = None
        try:
            up_reader, up_writer = await asyncio.open_connection("127.0.0.1", self._upstream_port)
            self._count("connections_accepted")
            up_writer.write(request)
            to_server = asyncio.ensure_future(self._to_server(reader, up_writer))
            try:  # the connection lasts until the server closes its side (it does when the client closes)
                await self._to_client(up_reader, writer, up_writer)
            finally:
                to_server.cancel()
        except (OSError, TimeoutError):
            pass  # a reset by either side, or a client that never takes the last bytes, ends the connection
        finally:
            self._clients.discard(task)
            self._on_clients(len(self._clients))
            if up_writer is not None:
                up_writer.transport.abort()

    async def _refuse(self, writer: asyncio.StreamWriter) -> None:
        self._note("connections_refused", f"refused a client: {self.max_clients} connected (the limit)")
        with contextlib.suppress(Exception):
            writer.write(REFUSAL)
            writer.close()
            await asyncio.wait_for(writer.wait_closed(), CLOSE_TIMEOUT_S)

    async def _to_client(self, src: asyncio.StreamReader, dst: asyncio.StreamWriter, upstream) -> None:
        """Server → client; pauses while the client is behind, drops it past the byte bound or the stall time."""
        while data := await src.read(READ_BYTES):
            if dst.transport.is_closing():
                return
            dst.write(data)
            if dst.transport.get_write_buffer_size() > self.max_buffer_bytes:
                return self._drop(dst, upstream, f"more than {self.max_buffer_bytes} bytes unsent")
            if dst.transport.get_write_buffer_size() > PAUSE_BYTES:  # the SDK's queue drops the oldest data
                try:
                    await asyncio.wait_for(dst.drain(), self.stall_s)
                except TimeoutError:
                    return self._drop(dst, upstream, f"nothing read for {self.stall_s} s")
        await asyncio.wait_for(dst.drain(), CLOSE_TIMEOUT_S)  # the server closed: flush, then close
        dst.write_eof()

    def _drop(self, dst: asyncio.StreamWriter, upstream: asyncio.StreamWriter, why: str) -> None:
        self._note("connections_dropped", f"dropped a client that stopped reading ({why})")
        dst.transport.abort()
        upstream.transport.abort()

    @staticmethod
    async def _to_server(src: asyncio.StreamReader, dst: asyncio.StreamWriter) -> None:
        """Client → server; the client's end of stream (or reset) is passed on, so the server closes too."""
        with contextlib.suppress(OSError):
            while data := await src.read(READ_BYTES):
                dst.write(data)
                await dst.drain()
        with contextlib.suppress(OSError):
            dst.write_eof()

    def _note(self, key: str, text: str) -> None:
        self._count(key)
        self._totals[key] += 1
        now = time.monotonic()
        if now - self._last_log.get(key, -LOG_PERIOD_S) >= LOG_PERIOD_S:
            self._last_log[key] = now
            log.warning("foxglove: %s; %d so far", text, self._totals[key])
