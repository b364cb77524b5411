"""Drive the WAM-V in the harbour with velocity commands (surge, sway, yaw rate) and print what it does.

    python examples/velocity_control.py [--seconds 60] [--allocator constrained|unconstrained]

A schedule of `cmd_vel`-style commands for base_link goes to a VesselController (gains derived from
the WAM-V's mass, inertia, drag and thrusters) running at 20 Hz inside the 100 Hz physics loop.
"""

from __future__ import annotations

import argparse

from usvsim.control import ControlLoop, VesselController
from usvsim.simulation import Simulation

# (start time s, (u m/s, v m/s, r rad/s)): ahead, turn to starboard (clear of the Otter and the dock), crab
# to port, stop
SCHEDULE = [(0.0, (1.5, 0.0, 0.0)), (8.0, (1.0, 0.0, -0.2)), (24.0, (0.0, 0.5, 0.0)), (36.0, (0.0, 0.0, 0.0))]


def command_at(t: float):
    return [cmd for start, cmd in SCHEDULE if t >= start][-1]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=50.0)
    parser.add_argument("--allocator", choices=["constrained", "unconstrained"], default="constrained")
    parser.add_argument("--print-every", type=float, default=2.5)
    args = parser.parse_args(argv)

    sim = Simulation.from_scenario("harbor")
    wamv = sim.vessels["wamv"]
    loop = ControlLoop(
        sim, "wamv", VesselController.for_model(wamv.model, allocator=args.allocator), rate_hz=20.0
    )
    every = round(args.print_every / sim.clock.dt)
    print(f"{'t [s]':>6} {'cmd u, v, r':>20} {'u [m/s]':>8} {'v [m/s]':>8} {'r [rad/s]':>9} {'x, y [m]':>16}")

    def on_step(s: Simulation) -> None:
        loop.reference = command_at(s.time)
        loop(s)
        if s.clock.steps % every == 0:
            u, v, _ = wamv.velocity_body
            r = wamv.angular_velocity_body[2]
            x, y, _ = wamv.position
            cmd = ", ".join(f"{c:.1f}" for c in loop.reference)
            print(f"{s.time:6.1f} {cmd:>20} {u:8.3f} {v:8.3f} {r:9.3f} {x:8.2f},{y:7.2f}")

    sim.run(args.seconds, on_step=on_step)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
