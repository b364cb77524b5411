"""Bridges between a running simulation and the outside: commands in (commands.py), live ROS 2 over DDS,
the ROS-TCP-Endpoint client and the Foxglove WebSocket server (each an optional extra, imported lazily)."""
