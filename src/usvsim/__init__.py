"""usvsim: a digital twin and simulation platform for unmanned surface vehicles."""

from pathlib import Path
from typing import TYPE_CHECKING

from usvsim.core.errors import ScenarioError, UsvsimError
from usvsim.core.numba_cache import isolate

isolate(Path(__file__).parent)  # numba's cache per version of the kernels (core/numba_cache.py): no stale kernels

if TYPE_CHECKING:  # for type checkers; at run time `__getattr__` imports them on first use
    from usvsim.config.loader import load_scenario
    from usvsim.simulation import Simulation

__all__ = ["ScenarioError", "Simulation", "UsvsimError", "load_scenario"]
__version__ = "0.1.0"


def __getattr__(name: str):
    # Lazy imports keep `import usvsim` cheap (no MuJoCo / numba start-up).
    if name == "Simulation":
        from usvsim.simulation import Simulation

        return Simulation
    if name == "load_scenario":
        from usvsim.config.loader import load_scenario

        return load_scenario
    raise AttributeError(name)
