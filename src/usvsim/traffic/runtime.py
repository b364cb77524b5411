"""`Traffic`: what the simulation loop holds for other ships: the fleet, the situational-awareness
publisher and the AIS transmitters. It takes the `World` (state) and the loop's controllers (which the
pilots of full-physics ships steer). Without `traffic.ships` every call returns at once."""

from __future__ import annotations

from typing import TYPE_CHECKING

from usvsim.messages.envelope import Envelope
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

    def before_step(self, world: World) -> None:
        if self._active:
            self.fleet.before_step(world)

    def on_step(self, world: World, publish: bool = True) -> list[Envelope]:
        """After the step (clock ticked, kinematics updated): messages due now (the situation message is only
        built when `publish`, i.e. someone listens; the run report is kept either way)."""
        if not self._active:
            return []
        self.fleet.update(world)
        out = self.situation.due(world, publish) if self.situation is not None else []
        return out + self.ais.due(world, publish) if self.ais is not None else out

    def report(self) -> dict:
        """Run report: per target the least distance to the own ship, when, and the least CPA predicted."""
        return self.situation.report() if self.situation is not None else {}

    def reset(self, world: World) -> None:
        self.fleet.reset(world)
        for part in (self.situation, self.ais):
            if part is not None:
                part.reset(world)

    def close(self) -> None:
        if self.ais is not None:
            self.ais.close()
