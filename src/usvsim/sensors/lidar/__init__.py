"""LiDAR: scan patterns, Embree ray world, water handling, the sensor."""
