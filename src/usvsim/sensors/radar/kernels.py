"""Numba kernels of the radar: fine-ray returns into spokes × range bins through the horizontal beam pattern."""

from __future__ import annotations

from numba import njit


@njit(cache=True)
def spread_returns(fine, bins, power, weights, oversampling, margin, out):
    """out[s, b] += weights[s, j] · p for each return (fine ray j, bin b, power p); spoke s only sees fine rays
    within `margin` spokes of its own (weights are negligible beyond)."""
    count = out.shape[0]
    for i in range(len(fine)):
        j = fine[i]
        centre = j // oversampling - margin  # the output spoke this fine ray lies in
        for s in range(max(centre - margin, 0), min(centre + margin + 1, count)):
            out[s, bins[i]] += weights[s, j] * power[i]
