"""Cameras: pinhole intrinsics + Brown–Conrady distortion, offscreen MuJoCo rendering, the sensor."""
