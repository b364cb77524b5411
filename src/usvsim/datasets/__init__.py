"""Synthetic labelled data sets with domain randomization (`usvsim dataset`)."""

from usvsim.datasets.generate import DatasetSpec, generate

__all__ = ["DatasetSpec", "generate"]
