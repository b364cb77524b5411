"""Many task runs at once: scenarios × seeds × parameter grids on local processes or Ray (`run`, `expand`)."""

from usvsim.batch.runner import RunSpec, expand, failed, run

__all__ = ["RunSpec", "expand", "failed", "run"]
