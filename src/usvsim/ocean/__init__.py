"""The ocean: the one water surface that physics, rendering and sensors all query."""

from usvsim.ocean.surface import FlatSea, WaterSurface

__all__ = ["FlatSea", "WaterSurface"]
