"""Sensors: config (`usvsim.config.sensors`) → scheduled sampler → ROS 2 messages. See `suite.SensorSuite`."""

from usvsim.sensors.base import Sensor
from usvsim.sensors.suite import SensorSuite

__all__ = ["Sensor", "SensorSuite"]
