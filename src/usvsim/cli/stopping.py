"""Ctrl-C (SIGINT) and SIGTERM (`kill`, `timeout`, `docker stop`, a job scheduler) stop a command between two
steps of its work, never inside one (where a recorder, a bridge or a file writer may be half-way through), so
what it writes is closed complete. `usvsim run` (headless and in the viewer, between frames), `usvsim task`,
`usvsim dataset` and `usvsim sweep` use it; each exits with the shell's status for the signal (130 for Ctrl-C, 143
for SIGTERM).

    with StopSignals() as stop:
        for step in work:
            stop.check()        # raises Stopped once a signal has arrived
"""

from __future__ import annotations

import signal

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


class Stopped(KeyboardInterrupt):
    """A stop signal (SIGINT or SIGTERM) taken between two steps."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


class StopSignals:
    """Records SIGINT and SIGTERM instead of raising them where they land; restores the handlers on exit."""

    def __init__(self) -> None:
        self.signum = 0
        self._previous: dict = {}

    def __enter__(self) -> StopSignals:
        self._previous = {s: signal.signal(s, self._record) for s in STOP_SIGNALS}
        return self

    def __exit__(self, *_exc) -> None:
        for s, handler in self._previous.items():
            signal.signal(s, handler)

    def _record(self, signum: int, _frame) -> None:
        self.signum = self.signum or signum

    def check(self, *_args) -> None:
        """Raise `Stopped` if a stop signal has arrived (takes and ignores arguments: usable as a step hook)."""
        if self.signum:
            raise Stopped(self.signum)


def signal_name(signum: int) -> str:
    """How the CLI names the stop: 'SIGTERM' or 'Ctrl-C'."""
    return "SIGTERM" if signum == signal.SIGTERM else "Ctrl-C"


def exit_status(signum: int) -> int:
    """The shell's status for a process ended by `signum` (130 for SIGINT, 143 for SIGTERM)."""
    return 128 + int(signum)
