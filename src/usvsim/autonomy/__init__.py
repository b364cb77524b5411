"""A small reference autonomy stack (docs/autonomy.md): LiDAR odometry, occupancy mapping, planning, LOS guidance,
reactive avoidance and goal logic, on the simulation's public message stream. Optional parts (KISS-ICP, rclpy)
are imported lazily."""
