"""A `/reset` from a bridge during a live task (`usvsim task --ros2`) is refused: it restarted the world's clock
under the task, so the trial ran on from t = 0 (longer than its time limit) with the score kept."""

from __future__ import annotations

from usvsim.tasks.live import run_live
from usvsim.tasks.timing import TaskTiming

EMPTY_CDR = b"\x00\x01\x00\x00\x00"  # std_msgs/msg/Empty, as `ros2 topic pub --once /reset std_msgs/msg/Empty`


class ResetPeer:
    """A bridge whose peer asks for /reset once the clock passes 1 s (through the command inbox, as DDS does)."""

    def __init__(self, sim):
        self.sim, self.stats = sim, {"resets_sent": 0}
        self._unsubscribe = sim.subscribe(self._on_message)

    def _on_message(self, envelope):
        if envelope.topic == "/clock" and envelope.stamp_ns >= 1_000_000_000 and not self.stats["resets_sent"]:
            assert self.sim.commands.post_cdr("/reset", EMPTY_CDR)  # queued; refused when applied
            self.stats["resets_sent"] = 1

    def close(self):
        self._unsubscribe()


def test_a_reset_during_a_live_trial_is_refused_and_counted():
    seen: dict = {}
    steps = [0]

    def count():
        steps[0] += 1

    timing = TaskTiming(ready_s=0.5, running_s=2.0)
    report = run_live("station_keeping", 0, 0, timing, bridges=lambda sim: [ResetPeer(sim)],
                      on_ready=lambda sim: seen.setdefault("sim", sim), after_step=count)  # fmt: skip
    sim = seen["sim"]
    assert report["bridges"]["ResetPeer"]["resets_sent"] == 1
    assert report["commands"]["rejected"] == 1 and report["commands"]["applied"] == 0
    assert sim.episode == 0 and report["sim_time_s"] == steps[0] * sim.clock.dt  # one episode, never restarted
    assert report["sim_time_s"] <= 2.5 + 0.01  # ready + running, not 1 s more
