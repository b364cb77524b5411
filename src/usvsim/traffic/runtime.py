"""`Traffic`: what the simulation loop holds for other ships: the fleet, the situational-awareness
publisher and the AIS transmitters. It takes the `World` (state) and the loop's controllers (which the
pilots of full-physics ships steer). Without `traffic.ships` every call returns at once."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from usvsim.messages.envelope import Envelope
from usvsim.traffic.colav import AvoidingPilot
from usvsim.traffic.fleet import Fleet
from usvsim.traffic.situation import SituationPublisher

if TYPE_CHECKING:
    from usvsim.world.world import World


class Traffic:
    def __init__(self, world: World, controllers: dict | None = None):
        cfg = world.scenario.traffic
        self.fleet = Fleet(world, controllers)
        self.situation = SituationPublisher(world, self.fleet, cfg.awareness) if len(self.fleet) else None
        self.ais = None
        if cfg.ais.enabled and (len(self.fleet) or cfg.ais.own_ship is not None):
            from usvsim.traffic.ais_publisher import AisPublisher  # pyais is imported only when AIS is on

            self.ais = AisPublisher(world, self.fleet, cfg.ais)
        self._active = len(self.fleet) > 0 or self.ais is not None
        if self._active:  # the loop calls the fleet directly: one Python call less per step
            self.before_step = self.fleet.before_step
        self._quiet_until = 0 if self._active else math.inf  # the next step at which on_step has work

    def before_step(self, world: World) -> None:
        """Kinematic ships to their poses at the end of the coming step, pilots' references (Fleet.before_step)."""

    def on_step(self, world: World, publish: bool = True) -> list[Envelope]:
        """After the step (clock ticked, kinematics updated): messages due now (the situation message is only
        built when `publish`, i.e. someone listens; the run report is kept either way). Steps with nothing due
        and nothing to refresh (kinematic ships are refreshed by before_step) cost one comparison."""
        if world.clock.steps < self._quiet_until:
            return []
        self.fleet.update(world)
        out = self.situation.due(world, publish) if self.situation is not None else []
        if self.ais is not None:
            out += self.ais.due(world, publish)
        self._quiet_until = self._next_busy_step(world)
        return out

    def _next_busy_step(self, world: World) -> float:
        steps = world.clock.steps
        if self.fleet.pilots:  # physics ships: their states are read after every step
            return steps + 1
        out = math.inf
        if self.situation is not None:
            out = (steps // self.situation.sample_every + 1) * self.situation.sample_every
        if self.ais is not None:  # a step early rather than late when the float time falls on a step
            out = min(out, max(steps + 1, math.floor(self.ais.next_due_s * 1e9 / world.clock.step_ns)))
        return out

    def report(self) -> dict:
        """Run report: per target the least distance to the own ship, when, the least CPA predicted within the
        TCPA limit and its TCPA, the range and TCPA at the end, the first hull contact (SituationPublisher.report);
        when the own ship avoids (`traffic.ships[].avoidance`), its COLREG role, alteration and whether it kept
        to starboard per target (AvoidingPilot.report)."""
        if self.situation is None:
            return {}
        out = self.situation.report()
        for name, pilot in self.fleet.pilots.values():
            if name == self.situation.own.name and isinstance(pilot, AvoidingPilot):
                for target, score in pilot.report().items():
                    if target in out:
                        out[target].update(score)
        return out

    def reset(self, world: World) -> None:
        self._quiet_until = 0 if self._active else math.inf
        self.fleet.reset(world)
        for part in (self.situation, self.ais):
            if part is not None:
                part.reset(world)

    def close(self) -> None:
        if self.ais is not None:
            self.ais.close()
