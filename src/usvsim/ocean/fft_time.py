"""Time interpolation of FFT tiles: each band is transformed only at its snapshot times t_m = m·Δ_b.

A query at time t ∈ [t_m, t_m+1) blends the eight snapshots m-3 … m+4 with Lagrange weights of degree 7 (`SNAPSHOTS`;
four, cubic, until 2026-11-27: the same error bound needed intervals 1.9-2.2x shorter; still four in choppy seas,
`SNAPSHOTS_CHOPPY`), so the FFT cost is paid
once per Δ_b instead of once per physics step. A snapshot is a pure function of its time, so the field at t does not
depend on which times were queried before (runs stay bit-identical for one seed, and a reset needs no special care).
Δ_b is the largest interval whose error bound meets the tolerance: a bin of frequency ω and variance v contributes at
most v·ε(ωΔ)² to the error variance, with ε(x) = max_u |e^{-ixu} - Σ_m w_m(u) e^{-ixm}| evaluated exactly (u on a
fine grid), so the rms error over the sea of a field weighted by ω^p (p = 0 height, 1 velocity, 2 acceleration) is
at most √(Σ v ω^{2p} ε²) — asserted against exact transforms in tests/ocean/test_ocean_fft_time.py.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numba import njit

SNAPSHOTS = 8  # snapshots blended per query (even): Lagrange polynomials of degree SNAPSHOTS - 1
# ... by a choppy sea (FFTWaveField): its queries blend per point and Newton iteration (no node cache), so more
# snapshots cost more than their longer intervals save (harbor, Phillips sea, 256²: 4 / 6 / 8 snapshots 1,507 /
# 1,576 / 1,864 µs CPU per step, one process, load 3.2)
SNAPSHOTS_CHOPPY = 4
MAX_INTERVAL_S = 2.0


def nodes_of(snapshots: int) -> np.ndarray:
    """The blended snapshots' offsets from the query's interval start m: 1 - snapshots/2 … snapshots/2 (float)."""
    if snapshots < 2 or snapshots % 2 or snapshots > 8:  # fft.PhaseTables keeps two bases: 9 snapshots at most
        raise ValueError(f"snapshots must be even, 2 to 8, got {snapshots}")
    return np.arange(1 - snapshots // 2, snapshots // 2 + 1, dtype=float)


NODES = nodes_of(SNAPSHOTS)


def _denominators(nodes: np.ndarray) -> np.ndarray:
    """Π_{j≠i} (x_i - x_j) per node (products of small integers: exact)."""
    return np.array([math.prod(float(xi - xj) for xj in nodes if xj != xi) for xi in nodes])


def lagrange_weights(u, nodes: np.ndarray | None = None):
    """Lagrange weights of `nodes` (default `NODES`, in units of the interval) at u; shape u.shape + (len(nodes),).
    The same operations as the compiled `_blend_weights`: the numerator's product in node order, over the exact
    denominator."""
    nodes = NODES if nodes is None else np.asarray(nodes, dtype=float)
    u = np.asarray(u, dtype=float)
    den = _denominators(nodes)
    out = np.empty(u.shape + (len(nodes),))
    for i in range(len(nodes)):
        num = np.ones(u.shape)
        for j, xj in enumerate(nodes):
            if j != i:
                num = num * (u - xj)
        out[..., i] = num / den[i]
    return out


def _error_table(nodes: np.ndarray, x_max: float = 40.0, n: int = 4001) -> tuple[np.ndarray, np.ndarray]:
    """ε(x) on [0, x_max], made non-decreasing (a bound between the table points); ≈ 1 ms to build."""
    u = np.linspace(0.0, 1.0, 65)
    w = lagrange_weights(u, nodes)  # (65, len(nodes))
    x = np.linspace(0.0, x_max, n)
    approx = np.exp(-1j * np.multiply.outer(x, nodes)) @ w.T  # (n, 65)
    eps = np.abs(np.exp(-1j * np.multiply.outer(x, u)) - approx).max(axis=1)
    return x, np.maximum.accumulate(eps)


_TABLES: dict[tuple, tuple[np.ndarray, np.ndarray, float]] = {}  # nodes → (x, ε(x), the bound beyond the table)


def error_factor(x: np.ndarray, nodes: np.ndarray | None = None) -> np.ndarray:
    """ε(x): largest |e^{-ixu} - Σ_m w_m(u) e^{-ixm}| over u ∈ [0, 1], x = ωΔ (tabulated, upper envelope), for the
    snapshots at `nodes` (default `NODES`)."""
    nodes = NODES if nodes is None else np.asarray(nodes, dtype=float)
    key = tuple(nodes.tolist())
    if key not in _TABLES:
        # beyond the table: |e^{-ixu}| + Σ|w_m(u)|, with the weights' largest absolute sum over u (a fine grid)
        beyond = float(np.abs(lagrange_weights(np.linspace(0.0, 1.0, 1025), nodes)).sum(axis=1).max() + 1.0)
        _TABLES[key] = (*_error_table(nodes), beyond)
    grid, eps, beyond = _TABLES[key]
    return np.interp(np.asarray(x, dtype=float), grid, eps, right=beyond)


def error_bound(variance: np.ndarray, omega: np.ndarray, interval_s: float, power: int = 0,
                nodes: np.ndarray | None = None) -> float:  # fmt: skip
    """Bound on the rms error (over the sea) of the field ω^power·η interpolated with snapshots `interval_s` apart."""
    keep = variance > 0
    v, w = variance[keep], omega[keep]
    return float(np.sqrt(np.sum(v * w ** (2 * power) * error_factor(w * interval_s, nodes) ** 2)))


def snapshot_interval(variance, omega, tolerance: float, total_rms, powers=(0, 1), nodes: np.ndarray | None = None
                      ) -> float:  # fmt: skip
    """Largest Δ (s, ≤ MAX_INTERVAL_S) with error_bound ≤ tolerance·total_rms[p] for every power p;
    inf for a band without energy (never transformed), 0 when `tolerance` is 0 (exact every query)."""
    if not np.any(variance > 0):
        return math.inf
    if tolerance <= 0:
        return 0.0
    keep = variance > 0
    v, w = variance[keep], omega[keep]

    def ok(dt):
        return all(error_bound(v, w, dt, p, nodes) <= tolerance * total_rms[p] for p in powers)

    lo, hi = 0.0, MAX_INTERVAL_S
    if ok(hi):
        return hi
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ok(mid) else (lo, mid)
    return lo


_NO_BASE = np.iinfo(np.int64).min  # a ring not filled yet


@njit(cache=True)
def _blend_weights(t, scale, intervals, base, nodes, den, weights, m_out):
    """Lagrange weights (`lagrange_weights` of `nodes`, the same operations, times `scale`) of every band with a
    finite, non-zero interval at time t into weights[band, ring entry]: node i's entry is (r + i) mod K with
    r = (m + nodes[0]) mod K, K = len(nodes), m = floor(t / Δ_b) (into m_out); den: `_denominators(nodes)`. Returns
    how many of those bands have m != base[band]. (Compiled: ~4 µs less per ring and step than Python.)"""
    k = nodes.shape[0]
    first = int(nodes[0])
    moved = 0
    for b in range(intervals.shape[0]):
        dt = intervals[b]
        if not (0.0 < dt < math.inf):
            continue
        m = math.floor(t / dt)
        m_out[b] = m
        if m != base[b]:
            moved += 1
        u = t / dt - m
        r = (m + first) % k
        for i in range(k):
            num = 1.0
            for j in range(k):
                if j != i:
                    num = num * (u - nodes[j])
            weights[b, (r + i) % k] = scale * (num / den[i])
    return moved


class SnapshotRing:
    """K = len(nodes) snapshots per band (default `NODES`), tiles[band, m mod K, slot] = the band's spatial tiles at
    time m·Δ_b."""

    def __init__(self, intervals, slots: int, n: int, compute: Callable[[int, float, np.ndarray], None],
                 nodes: np.ndarray | None = None):  # fmt: skip
        self.intervals = [float(d) for d in intervals]
        self.nodes = np.array(NODES if nodes is None else nodes, dtype=float)
        self._den = _denominators(self.nodes)
        k = len(self.nodes)
        bands = len(self.intervals)
        self.tiles = np.zeros((bands, k, slots, n, n), np.complex64)
        self.weights = np.zeros((bands, k))
        self._held = np.full((bands, k), np.nan)  # the snapshot time each ring entry holds
        self._compute = compute  # compute(band, t, out (slots, n, n)) writes the band's tiles at time t
        self._dt = np.array(self.intervals)
        self._base = np.full(bands, _NO_BASE, np.int64)  # the interval index m each band's ring was last filled for
        self._m = np.zeros(bands, np.int64)  # scratch: each band's interval index at the time being prepared
        self._exact = [b for b, dt in enumerate(self.intervals) if dt == 0.0]
        self._key = None
        self.transforms = 0  # snapshots computed so far (for tests and benchmarks)
        # Computing ahead (set by the owner, see FFTWaveField): fetch(b, t, out) -> bool installs a snapshot made
        # beforehand (False: none, compute it here); ahead(b, t) asks for band b's snapshot at t to be made now,
        # e.g. on another core. Called with the next snapshot time whenever a band steps into its next interval.
        self.fetch: Callable[[int, float, np.ndarray], bool] | None = None
        self.ahead: Callable[[int, float], None] | None = None

    def prepare(self, t: float, scale: float) -> np.ndarray:
        """Make the snapshots around t present; return the blend weights (bands, K), multiplied by `scale`."""
        if self._key == (t, scale):
            return self.weights
        moved = _blend_weights(float(t), float(scale), self._dt, self._base, self.nodes, self._den, self.weights,
                               self._m)  # fmt: skip
        for b in self._exact:  # time_tolerance 0: a transform at every queried time
            self._ensure(b, 0, t)
            self.weights[b, 0] = scale
        stepped = []  # bands that moved on to their next interval
        if moved:
            for b, dt in enumerate(self.intervals):
                m, base = int(self._m[b]), int(self._base[b])
                if not (0.0 < dt < math.inf) or m == base:
                    continue
                first, k = int(self.nodes[0]), len(self.nodes)
                for i in range(k):  # a new interval: bring in the missing snapshots m + nodes[0] … m + nodes[-1]
                    self._ensure(b, (m + first + i) % k, (m + first + i) * dt)
                if base != _NO_BASE and m == base + 1:
                    stepped.append((b, (m + first + k) * dt))  # the one the next interval brings in (same expression)
                self._base[b] = m
        self._key = (t, scale)
        if self.ahead is not None:
            for b, t_next in stepped:
                self.ahead(b, t_next)
        return self.weights

    def _ensure(self, b: int, r: int, t: float) -> None:
        if self._held[b, r] != t:
            if self.fetch is None or not self.fetch(b, t, self.tiles[b, r]):
                self._compute(b, t, self.tiles[b, r])
            self._held[b, r] = t
            self.transforms += 1
