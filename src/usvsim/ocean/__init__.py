"""The ocean: the one water surface that physics, rendering and sensors all query."""

from usvsim.ocean.build import build_ocean
from usvsim.ocean.components import WaveComponents
from usvsim.ocean.current import Current
from usvsim.ocean.direct import DirectWaveField
from usvsim.ocean.fft import FFTWaveField
from usvsim.ocean.ocean import Ocean
from usvsim.ocean.patch import WaterPatch
from usvsim.ocean.surface import FlatSea, WaterSurface
from usvsim.ocean.wind import Wind

__all__ = [
    "Current",
    "DirectWaveField",
    "FFTWaveField",
    "FlatSea",
    "Ocean",
    "WaterPatch",
    "WaterSurface",
    "WaveComponents",
    "Wind",
    "build_ocean",
]
