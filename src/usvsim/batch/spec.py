"""`usvsim sweep SPEC.yaml`: what to run. Every list is one axis of the grid; runs are the product.

```yaml
task: station_keeping          # or a list of tasks
difficulty: [0, 1]
seeds: [0, 1, 2, 3]            # or {start: 0, count: 8}
time_limit_s: 30
grid:
  mass_kg: [180, 250]          # WAM-V mass override
  sea_state: [null, 3]         # WMO code instead of the level's VRX sea
  hold: {position_gain_1ps: [0.25, 0.4]}   # reference controller gains (config.control.Hold keys)
backend: process               # or ray
workers: 2
```
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from usvsim.config.base import PositiveFloat, Section


class SeedRange(Section):
    start: int = 0
    count: Annotated[int, Field(ge=1)]


GridValue = float | int | None


class Grid(Section):
    mass_kg: list[PositiveFloat | None] = [None]
    sea_state: list[Annotated[int, Field(ge=0, le=9)] | None] = [None]
    hold: dict[str, list[PositiveFloat]] = Field(default_factory=dict, description="Hold key → values")


class SweepSpec(Section):
    task: str | list[str] = "station_keeping"
    difficulty: int | list[int] = 0
    seeds: list[int] | SeedRange = [0]
    time_limit_s: Annotated[float, Field(gt=0, le=1e6)] = 60.0  # at most ~11.6 days a run
    grid: Grid = Grid()
    backend: Literal["process", "ray"] = "process"
    workers: Annotated[int, Field(ge=1)] | None = None
    address: str | None = Field(default=None, description="Ray cluster address; default a local instance")

    @model_validator(mode="after")
    def _runnable(self):
        """Every run of the grid can start: checked here, before the first run, not in a worker's traceback."""
        from usvsim.config.control import Hold
        from usvsim.tasks.levels import LEVELS
        from usvsim.tasks.library import TASKS

        axes = [("task", self.task), ("difficulty", self.difficulty), ("seeds", self.seed_list()),
                ("grid.mass_kg", self.grid.mass_kg), ("grid.sea_state", self.grid.sea_state),
                *((f"grid.hold.{k}", v) for k, v in self.grid.hold.items())]  # fmt: skip
        for key, values in axes:  # an empty grid list was 0 runs, exit status 0
            if isinstance(values, list) and not values:  # no run at all (was a ZeroDivisionError in the mean score)
                raise ValueError(f"{key}: give at least one")
        for name in [self.task] if isinstance(self.task, str) else self.task:
            if name not in TASKS:
                raise ValueError(f"task: unknown task {name!r}; choose from {', '.join(TASKS)}")
        for level in [self.difficulty] if isinstance(self.difficulty, int) else self.difficulty:
            if level not in LEVELS:
                raise ValueError(f"difficulty: {level} is not one of {sorted(LEVELS)}")
        if any(seed < 0 for seed in self.seed_list()):
            raise ValueError("seeds: a seed is a non-negative integer")
        unknown = sorted(set(self.grid.hold) - set(Hold.model_fields))
        if unknown:
            raise ValueError(
                f"grid.hold: unknown key(s) {unknown}; Hold keys: {', '.join(Hold.model_fields)}"
            )
        return self

    def seed_list(self) -> list[int]:
        s = self.seeds
        return list(range(s.start, s.start + s.count)) if isinstance(s, SeedRange) else list(s)
