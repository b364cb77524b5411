"""Other ships: kinematic and full-physics traffic, encounters (Imazu), ground-truth situational awareness
(CPA/TCPA, COLREG), AIS. The radar that sees them is a sensor (`usvsim.sensors.radar`)."""

from usvsim.traffic.fleet import kinematic_bodies
from usvsim.traffic.runtime import Traffic

__all__ = ["Traffic", "kinematic_bodies"]
