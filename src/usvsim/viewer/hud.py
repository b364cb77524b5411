"""Head-up display text from the simulation state (pure: no GL). Two columns, for `mujoco.mjr_overlay`."""

from __future__ import annotations

import math
from dataclasses import dataclass

KNOTS_PER_MPS = 3600.0 / 1852.0
HELP = (
    "W/S throttle  A/D steer  R reset  Space pause  N/Right step  C follow  P shot  drag orbit  scroll zoom  Esc quit"
)


@dataclass
class RateMeter:
    """Exponential moving averages of frames per second and real-time factor (the seed's FPS counter: α = 0.1)."""

    alpha: float = 0.1
    fps: float = 0.0
    rtf: float = 0.0

    def update(self, wall_dt: float, sim_dt: float) -> None:
        if wall_dt <= 0:
            return
        if self.fps == 0.0:
            self.fps, self.rtf = 1.0 / wall_dt, sim_dt / wall_dt
        else:
            self.fps += self.alpha * (1.0 / wall_dt - self.fps)
            self.rtf += self.alpha * (sim_dt / wall_dt - self.rtf)


def compass_heading_deg(yaw_rad: float) -> float:
    """Nautical heading (clockwise from north, 0–360°) of an ENU yaw (CCW from east)."""
    return (90.0 - math.degrees(yaw_rad)) % 360.0


def hud_lines(sim, vessel_name: str, rates: RateMeter | None = None, paused: bool = False, follow: bool = True,
              axes=None) -> list[tuple[str, str]]:  # fmt: skip
    """(label, value) rows: vessel, speed, heading, per-thruster thrust and angle, time, RTF, fps, mode."""
    vessel = sim.vessels[vessel_name]
    u, v, _ = vessel.velocity_body
    speed = math.hypot(u, v)
    yaw = float(vessel.rpy[2])
    rows = [
        ("Vessel", vessel_name),
        ("Speed", f"{speed:5.2f} m/s  {speed * KNOTS_PER_MPS:5.2f} kn  (surge {u:+.2f})"),
        ("Heading", f"{compass_heading_deg(yaw):5.1f} deg  (yaw {math.degrees(yaw):+6.1f})"),
    ]
    for name, thruster in vessel.thrusters.items():
        wet = thruster.immersion
        dry = f"  {100 * wet:3.0f}% wet" if wet < 1.0 else ""  # a propeller out of the water
        rows.append((name, f"{thruster.thrust_n:+8.1f} N  {math.degrees(thruster.angle_rad):+6.1f} deg{dry}"))
    rows.append(("Sim time", f"{sim.time:8.2f} s"))
    if rates is not None:
        rows += [("Real-time", f"{rates.rtf:5.2f} x"), ("FPS", f"{rates.fps:5.1f}")]
    if axes is not None:
        rows.append(("Throttle/steer", f"{axes.throttle:+.2f} / {axes.steering:+.2f}"))
    rows.append(("Mode", ("PAUSED" if paused else "running") + ("  follow cam" if follow else "  orbit cam")))
    return rows


def overlay_columns(rows: list[tuple[str, str]]) -> tuple[str, str]:
    """The two newline-joined columns `mjr_overlay` draws."""
    return "\n".join(r[0] for r in rows), "\n".join(r[1] for r in rows)
