"""FFT wave field after Tessendorf: several periodic tiles (cascades) of different sizes, choppy displacement.

Each band b is an N×N periodic tile (N a power of two) of side L_b (world ENU, metres). Band b owns the wave vectors with
K_b ≤ |k| < K_{b+1}, K_0 = 0, K_{b+1} = 2π N / (8 L_b), the last band up to its Nyquist, so no wave is counted
twice and every wave of a band but the last has ≥ 8 cells per wavelength (bilinear error ≤ 8 % of its amplitude,
1.4 % of σ overall for JONSWAP Hs 2 m Tp 8 s at N = 256). Tile sizes that are
not small-integer multiples of each other keep the repetition invisible. Deep-water dispersion ω = √(g k), exact per
bin (no time quantisation). A bin's complex amplitude is c = √(2 S(k) Δk²) e^{iφ} (deterministic amplitude,
random phase; variance exact) or, with `gaussian_amplitudes`, c = (ξ1 + i ξ2) √(S Δk²) as in Tessendorf.
Heights at world points invert the displacement by Newton's method on the bilinear tiles: tolerance `tol`
(default 1e-9 m horizontal residual), at most `max_iter` (default 20) iterations. Tiles are transformed at
snapshot times and blended in time (`fft_time`): `time_tolerance` bounds the interpolation error (rms over the
sea, relative to the sea's rms height, vertical velocity and acceleration); 0 transforms at every queried time.

What does not depend on the random draw (each bin's variance, wave vectors and frequencies, the snapshot intervals,
which use the bins' expected variance) is kept per process for a `spectrum_key` (`FFTTables`): a second field of the
same sea, e.g. after `World.reset`, only draws its amplitudes. The tables are the same numbers a first build makes,
so a field is bit-identical with or without them.
"""

from __future__ import annotations

import importlib
import math
import os
import time
from collections import OrderedDict
from collections.abc import Callable, Hashable
from concurrent.futures import Future
from dataclasses import dataclass, field
from functools import partial
from typing import Literal, overload

import numpy as np

from usvsim.core.overlap import Overlap
from usvsim.ocean import fft_kernels as kern
from usvsim.ocean import fft_time
from usvsim.ocean.components import WaveComponents
from usvsim.ocean.dispatch import pick
from usvsim.ocean.fft_time import SnapshotRing, snapshot_interval
from usvsim.ocean.field import Labels, LabelsIterations, WaveField, as_points
from usvsim.ocean.spectra import G, cos2s

Spectrum2D = Callable[[np.ndarray, np.ndarray, int], np.ndarray]


def directional_spectrum(
    s_omega: Callable[[np.ndarray], np.ndarray], direction: float, s: float
) -> Spectrum2D:
    """Wavenumber spectrum S(kx, ky) = S(ω) D(θ) (dω/dk)/k, deep water (dω/dk = ω/(2k)), m⁴; same for all bands."""

    def spectrum(kx, ky, band):
        k = np.hypot(kx, ky)
        safe = np.where(k > 0, k, 1.0)
        omega = np.sqrt(G * safe)
        value = s_omega(omega) * cos2s(np.arctan2(ky, kx), direction, s) * omega / (2.0 * safe**2)
        return np.where(k > 0, value, 0.0)

    return spectrum


def cascade_sizes(peak_wavelength_m: float, bands: int = 3, resolution: int = 256) -> tuple[float, ...]:
    """Default tile sizes: the largest 10 peak wavelengths (≥ 50 m), each next one 7.3 times smaller (at most
    0.95 N/32 times, the widest step `FFTWaveField` accepts)."""
    largest = max(10.0 * peak_wavelength_m, 50.0)
    ratio = min(7.3, 0.95 * resolution / (4 * FFTWaveField.CELLS_PER_WAVELENGTH))
    return tuple(largest / ratio**b for b in range(bands))


def _bin_variance(spectrum, band, kx, ky, dk, k_lo, k_hi, sub: int = 4) -> np.ndarray:
    """Variance (m²) of each bin: S integrated over the bin's cell ∩ the band's annulus k_lo ≤ |k| < k_hi
    (midpoint rule on sub×sub points). Integrating instead of sampling S at the centre keeps a narrow
    spectral peak's variance, and the bands' annuli partition the k-plane exactly (no gap, no overlap)."""
    total = np.zeros_like(kx)
    for ox in ((np.arange(sub) + 0.5) / sub - 0.5) * dk:
        for oy in ((np.arange(sub) + 0.5) / sub - 0.5) * dk:
            sx, sy = kx + ox, ky + oy
            k = np.hypot(sx, sy)
            total += np.where((k >= k_lo) & (k < k_hi), spectrum(sx, sy, band), 0.0)
    return total * dk**2 / sub**2


@dataclass
class FFTTables:
    """The draw-independent tables of one sea (spectrum, tile sizes, resolution), shared read-only by its fields:
    per band (bands, N, N) the bin variance (m², the expected |c|²/2), ω, unit wave vector and wave vector, and
    the snapshot intervals per (time tolerance, powers)."""

    var: np.ndarray
    omega: np.ndarray
    khx: np.ndarray
    khy: np.ndarray
    kx: np.ndarray
    ky: np.ndarray
    intervals: dict = field(default_factory=dict)


_TABLES: OrderedDict[Hashable, FFTTables] = OrderedDict()
TABLES_KEPT = 8  # seas whose tables a process keeps (about 3.3 MB each at 3 bands of 256²)


def _bilinear_gain(k_times_cell: np.ndarray) -> np.ndarray:
    """Mean over positions of the variance that bilinear interpolation keeps of a wave, per axis:
    (2 + cos(k h))/3 (h the cell size). Bins are amplified by 1/√(gain_x gain_y), so the interpolated sea has
    the spectrum's variance on average over positions (vertices read up to 1/gain high, cell centres
    cos²(k h/2)/gain; at the default cascade ≤ ±2 % in Hs)."""
    return (2.0 + np.cos(k_times_cell)) / 3.0


def pair_bins(amp: np.ndarray) -> np.ndarray:
    """(bands, N, N) bool: the bins whose e^{-iωt} the spectra kernels read: the canonical bin of each (k, -k)
    pair (`fft_kernels._rows`) of which at least one has an amplitude."""
    n = amp.shape[1]
    mirror = np.roll(amp[:, ::-1, ::-1], 1, axis=(1, 2))  # mirror[b, iy, ix] = amp[b, (n - iy) % n, (n - ix) % n]
    live = (amp != 0) | (mirror != 0)
    canonical = np.zeros((n, n), bool)
    canonical[: n // 2 + 1] = True
    canonical[0, n // 2 + 1 :] = canonical[n // 2, n // 2 + 1 :] = False
    return live & canonical[None]


class PhaseTables:
    """e^{-iω t} of every bin at a band's snapshot times t = m Δ_b without a sine and cosine per bin: m = 8 q + r,
    e^{-iω m Δ} = A_q · P1^(bit 0 of r) · P2^(bit 1) · P4^(bit 2), with P_j = e^{-iω j Δ} made once and A_q =
    e^{-iω 8 q Δ} made (by sine and cosine) when a snapshot needs a new q (every 8 snapshots; two kept, as the
    consecutive snapshots of a ring, at most 9, may straddle a boundary). A snapshot is still a function of its
    time alone (the same products whatever was queried before); the rotation is within a few 1e-16 of the direct one. Times
    off the band's snapshot grid (time_tolerance 0, or a band never transformed) use the sine and cosine.

    Only the bins the spectra kernel reads are filled (`used`, see `pair_bins`; the rest are 0): half the
    spectrum at most, 5 % of it in the long bands of a cascade (each the same numpy operation on the same value,
    so the same bits as made over the whole band)."""

    SPAN = 8

    def __init__(self, omega: np.ndarray, intervals, used: np.ndarray | None = None):
        self._omega, self._dt = omega, [float(d) for d in intervals]
        self._idx = [np.flatnonzero(np.ones(omega[b].shape, bool) if used is None else used[b])
                     for b in range(len(omega))]  # fmt: skip
        self._steps: dict[int, np.ndarray] = {}  # band → (4, N, N): slot 0 for A_q, then P1, P2, P4
        self._base: dict[int, dict[int, np.ndarray]] = {}  # band → {q: A_q at the used bins}
        self._held: dict[int, int | None] = {}  # band → the q whose A_q is in slot 0
        self._none = np.zeros((4, 1, 1), np.complex128)

    def at(self, b: int, t: float) -> tuple[np.ndarray, int]:
        """(phases, bits) for `geometry_and_velocity_spectra` at time t of band b; bits -1: evaluate e^{-iωt}."""
        dt = self._dt[b]
        if not (0.0 < dt < math.inf):
            return self._none, -1
        m = round(t / dt)
        if m * dt != t:  # not a snapshot time of this band's ring
            return self._none, -1
        q, r = divmod(m, self.SPAN)
        table, idx = self._steps.get(b), self._idx[b]
        if table is None:
            w = self._omega[b].reshape(-1)[idx]
            table = self._steps[b] = np.zeros((4, *self._omega[b].shape), np.complex128)
            for slot, j in ((1, 1), (2, 2), (3, 4)):
                table[slot].reshape(-1)[idx] = np.exp(-1j * w * (j * dt))
            self._base[b], self._held[b] = {}, None
        if self._held[b] != q:  # slot 0 holds A_q
            bases = self._base[b]
            if q not in bases:
                if len(bases) >= 2:
                    del bases[next(iter(bases))]  # the older one
                phase = self._omega[b].reshape(-1)[idx] * (q * self.SPAN * dt)
                bases[q] = np.cos(phase) - 1j * np.sin(phase)
            table[0].reshape(-1)[idx], self._held[b] = bases[q], q
        return table, r


_AHEAD = Overlap()  # the worker thread that makes geometry snapshots ahead of their time (one per process)


def _second_core() -> bool:
    try:
        return len(os.sched_getaffinity(0)) > 1
    except AttributeError:  # not on Linux
        return (os.cpu_count() or 1) > 1


_C2C: list = []  # pocketfft_c2c's finding, once per process


def pocketfft_c2c():
    """scipy.fft.ifft2's own C++ transform (pocketfft's c2c in a private compiled module, called into a given array
    by `FFTWaveField._ifft2_into`), if this scipy has it with the signature used here and it gives ifft2's bytes on
    a small check; else None. A private module may change in any scipy release: then the sea falls back to the
    public function (the same bytes, one copy more) instead of failing mid-run."""
    if not _C2C:
        import scipy.fft

        x = (np.arange(2 * 8 * 8, dtype=np.float32).reshape(2, 8, 8) * np.complex64(0.3 - 0.7j)).astype(np.complex64)
        out = np.empty_like(x)
        try:
            c2c = importlib.import_module("scipy.fft._pocketfft.pypocketfft").c2c
            c2c(x, (1, 2), False, 0, out, 1)
            ok = out.tobytes() == np.asarray(scipy.fft.ifft2(x, norm="forward", workers=1)).tobytes()
        except (ImportError, AttributeError, TypeError, ValueError, RuntimeError):
            c2c, ok = None, False
        _C2C.append(c2c if ok else None)
    return _C2C[0]


class FFTWaveField(WaveField):
    """Cascaded FFT tiles; implements `WaterSurface`. Snapshots are transformed lazily when a query needs them.

    Ahead of time: when a band steps into its next snapshot interval, the snapshot that the interval after it
    will bring in is started on a worker thread (`core.overlap`; the spectra kernel and scipy's FFT release the
    GIL), so a steadily advancing simulation finds it made and only copies it in; its velocity tiles too where
    the velocity ring snapshots the band at the same times. The same kernels on the same inputs: the sea is
    bit-identical with or without it (`AHEAD`), whatever the timing; the main thread waits where the worker is
    not done. It moves CPU time to the second core (less wall time per step where that core is free, a little
    more CPU time); off by default (see `AHEAD`)."""

    CELLS_PER_WAVELENGTH = 8  # a band hands its waves to the next band below this many cells per wavelength
    # Make geometry snapshots ahead on a worker thread (only with time interpolation, >= 2 cores). Off unless
    # USVSIM_FFT_AHEAD=1: it lowers the wall time per step only where a core is free (harbor SS4 at load 2.1:
    # 95.6 vs 112.5 us) and cost 3-20 us wall and 4-7 us CPU per step at loads 2.6-4.2 on the 2-core machine
    # (docs/seas.md), as in RL or batch runs with a process per core.
    AHEAD = os.environ.get("USVSIM_FFT_AHEAD", "0") == "1"
    SPARSE = 0.25  # a band with an amplitude in fewer than this fraction of its pairs loops over those only
    # (SS4 cascade: 5 % in the long bands, 28 -> 6 us per snapshot; the fine band, 97 %, is faster with the full pass)

    def __init__(
        self,
        spectrum: Spectrum2D,
        tile_sizes_m,
        rng: np.random.Generator,
        resolution: int = 256,
        choppiness: float = 0.0,
        ramp_time_s: float = 0.0,
        gaussian_amplitudes: bool = False,
        tol: float = 1e-9,
        max_iter: int = 20,
        time_tolerance: float = 1e-3,
        spectrum_key: Hashable | None = None,
    ):
        """`spectrum_key`: a hashable description of `spectrum` (equal keys: the same function), under which the
        draw-independent tables are kept for later fields of the same sea (None: computed for this field only)."""
        super().__init__(ramp_time_s)
        import scipy.fft  # here: ~0.4 s to import, and only FFT seas need it (a process start pays it otherwise)

        self._ifft2 = scipy.fft.ifft2
        self._c2c = pocketfft_c2c()  # None: the public function and a copy (_ifft2_into)
        self.sizes = np.asarray(tile_sizes_m, dtype=float)
        self.n = int(resolution)
        self.choppiness = float(choppiness)
        # snapshots blended per query (fft_time): seas without displacement blend each tile node once per step
        # (node cache), choppy ones per point and Newton iteration, where more snapshots cost more than they save
        self.snapshots = fft_time.SNAPSHOTS if self.choppiness == 0.0 else fft_time.SNAPSHOTS_CHOPPY
        self.tol, self.max_iter = float(tol), int(max_iter)
        if self.n < 8 or self.n & (self.n - 1):
            raise ValueError(f"resolution must be a power of two >= 8, got {self.n}")
        key = None if spectrum_key is None else (spectrum_key, tuple(self.sizes.tolist()), self.n)
        tables = _TABLES.get(key) if key is not None else None
        if tables is None:
            tables = self._tables(spectrum)
            if key is not None:
                _TABLES[key] = tables
                while len(_TABLES) > TABLES_KEPT:
                    _TABLES.popitem(last=False)
        elif key is not None:
            _TABLES.move_to_end(key)
        self._tables_of = tables
        self._var, self._omega, self._khx, self._khy = tables.var, tables.omega, tables.khx, tables.khy
        self._kx, self._ky = tables.kx, tables.ky
        self._amp = np.zeros(tables.var.shape, np.complex128)
        for b in range(len(self.sizes)):  # draws in band order: the same stream use as one band at a time
            var = self._var[b]
            if gaussian_amplitudes:
                xi = rng.standard_normal((2, self.n, self.n))
                self._amp[b] = (xi[0] + 1j * xi[1]) * np.sqrt(var)
            else:
                self._amp[b] = np.sqrt(2.0 * var) * np.exp(2j * math.pi * rng.random((self.n, self.n)))
        self.inv_cells = self.n / self.sizes
        self.decay_k = self._decay_wavenumbers()
        self._spec = np.zeros((3, self.n, self.n), np.complex64)  # one band's spectra (scratch)
        self._vel_spectra: dict[tuple[int, float], np.ndarray] = {}  # (band, t) → velocity spectrum made beside
        self._node_heights = np.zeros((len(self.sizes), self.n, self.n))  # see node_cache
        self._node_stamp = np.zeros((len(self.sizes), self.n, self.n), np.int64)
        self._node_key, self._node_now = None, 0
        self._scratch: dict[tuple[str, int], np.ndarray] = {}  # see scratch
        self._updated: tuple[float, object] = (math.nan, None)  # see update: its last time and the ring's key then
        self.geometry = self._ring(
            time_tolerance, (0, 1), 2 if self.choppiness else 1, self._geometry_snapshot
        )
        used = pair_bins(self._amp)
        self._phases = PhaseTables(self._omega, self.geometry.intervals, used)
        # bands with an amplitude in few bins (the long ones of a cascade: ~5 %) make their spectra pair by pair
        canonical = self.n * self.n // 2 + 2
        self._pairs = [np.argwhere(used[b]) if used[b].sum() < self.SPARSE * canonical else None
                       for b in range(len(self.sizes))]  # fmt: skip
        self._sparse: dict[int, tuple[np.ndarray, np.ndarray]] = {}  # band → (spectra, velocity) kept zero elsewhere
        self._columns = [self._column_blocks(p) for p in self._pairs]  # sparse bands' nonzero columns (see _ifft2_into)
        self._pruned: dict[tuple[bool, int, int], np.ndarray] = {}  # their intermediate arrays, zero between blocks
        # Velocity (power 1) at the geometry's times: the geometry bound (powers 0 and 1) is the stricter one, so
        # its interval is never longer, and every velocity spectrum is then made in the geometry pass (and ahead).
        self.velocity_ring = SnapshotRing(self.geometry.intervals, 1, self.n, partial(self._kinematic_snapshot, False),
                                          self.geometry.nodes)  # fmt: skip
        self.acceleration_ring = self._ring(time_tolerance, (2,), 2, partial(self._kinematic_snapshot, True))
        self._jobs: dict[int, tuple[float, int, bool, Future, float, float]] = {}  # band → (t, buffer set, with
        # velocity, the worker's job, wall clock and this thread's CPU time at its start) of a snapshot made ahead
        self._ahead_pause = [0] * len(self.sizes)  # per band: intervals left to compute here (see _fetch_ahead)
        self._ahead_backoff = [self.AHEAD_PAUSE // 2] * len(self.sizes)  # per band: half the next pause
        self._jobs_pid = os.getpid()  # the process whose worker runs the jobs (a forked child has none of them)
        self.ahead_stats = [0, 0]  # snapshots taken from the worker: in time on a core of its own, or not
        self._ahead_bufs: tuple[np.ndarray, ...] | None = None  # see _start_ahead
        self._ahead_next = [0] * len(self.sizes)  # the buffer set each band's next job writes
        self._vel_made: dict[tuple[int, float], int] = {}  # (band, t) → buffer set holding its velocity tiles
        if self.AHEAD and time_tolerance > 0 and _second_core():
            self.geometry.fetch, self.geometry.ahead = self._fetch_ahead, self._start_ahead

    def _ring(self, tolerance: float, powers, slots: int, compute) -> SnapshotRing:
        """Snapshots whose interval per band bounds the error of ω^p η for every p in `powers` (η, w: 0, 1;
        velocity 1; acceleration 2) to `tolerance` of that field's rms over the sea, for the bins' expected
        variance (the spectrum's: the same for every draw of the sea)."""
        cached = self._tables_of.intervals
        nodes = fft_time.nodes_of(self.snapshots)
        key = (float(tolerance), tuple(powers), tuple(nodes.tolist()))
        if key not in cached:
            var = self._var
            rms = [math.sqrt(float(np.sum(var * self._omega ** (2 * p)))) for p in range(3)]
            active = max(int(np.count_nonzero(var.sum(axis=(1, 2)))), 1)
            tol = float(tolerance) / math.sqrt(active)  # the bands' errors add in variance
            cached[key] = [snapshot_interval(var[b], self._omega[b], tol, rms, powers, nodes)
                           for b in range(len(self.sizes))]  # fmt: skip
        return SnapshotRing(cached[key], slots, self.n, compute, nodes)

    @property
    def snapshot_intervals_s(self) -> dict[str, list[float]]:
        """Time between transforms of each band (s): inf = a band without energy, 0 = every queried time."""
        rings = {
            "geometry": self.geometry,
            "velocity": self.velocity_ring,
            "acceleration": self.acceleration_ring,
        }
        return {name: ring.intervals for name, ring in rings.items()}

    def _band_limits(self) -> list[float]:
        if np.any(np.diff(self.sizes) >= 0):
            raise ValueError(f"tile sizes must decrease strictly, got {self.sizes.tolist()}")
        limits = [0.0]
        for b in range(len(self.sizes) - 1):
            cut = 2.0 * math.pi * self.n / (self.CELLS_PER_WAVELENGTH * self.sizes[b])
            if cut < 4 * 2 * math.pi / self.sizes[b + 1]:
                need = 2 * math.ceil(2.0 * self.CELLS_PER_WAVELENGTH * self.sizes[b] / self.sizes[b + 1])
                raise ValueError(
                    f"tiles {self.sizes[b]:g} m and {self.sizes[b + 1]:g} m are too far apart for resolution {self.n} "
                    f"(size ratio at most resolution/{4 * self.CELLS_PER_WAVELENGTH}); use resolution >= {need} "
                    "or closer tile sizes"
                )
            limits.append(cut)
        return limits + [math.inf]

    def _tables(self, spectrum: Spectrum2D) -> FFTTables:
        limits = self._band_limits()
        shape = (len(self.sizes), self.n, self.n)
        t = FFTTables(np.zeros(shape), np.zeros(shape), np.zeros(shape), np.zeros(shape), np.zeros(shape),
                      np.zeros(shape))  # fmt: skip
        for b, size in enumerate(self.sizes):
            k1 = 2.0 * math.pi * np.fft.fftfreq(self.n, d=size / self.n)
            kx, ky = np.meshgrid(k1, k1)
            k = np.hypot(kx, ky)
            nyquist = (np.abs(kx) >= math.pi * self.n / size - 1e-9) | (
                np.abs(ky) >= math.pi * self.n / size - 1e-9
            )
            owned = (k > 0) & ~nyquist
            var = np.where(owned, _bin_variance(spectrum, b, kx, ky, 2.0 * math.pi / size, limits[b], limits[b + 1]),
                           0.0)  # fmt: skip
            var /= _bilinear_gain(kx * size / self.n) * _bilinear_gain(ky * size / self.n)
            safe = np.where(k > 0, k, 1.0)
            t.var[b], t.omega[b] = var, np.sqrt(G * k)
            t.khx[b], t.khy[b] = kx / safe, ky / safe
            t.kx[b], t.ky[b] = kx, ky
        return t

    def _decay_wavenumbers(self) -> np.ndarray:
        """Per band, the mean k weighted by velocity variance |c|² ω²: the band's depth attenuation rate."""
        weight = np.abs(self._amp) ** 2 * self._omega**2
        k = self._omega**2 / G
        total = weight.sum(axis=(1, 2))
        return np.where(total > 0, (weight * k).sum(axis=(1, 2)) / np.where(total > 0, total, 1.0), 0.0)

    def _start_ahead(self, b: int, t: float) -> None:
        """Start band b's geometry snapshot at t on the worker thread, into one of two buffer sets per band (the
        velocity tiles of the previous job may still wait for the velocity ring in the other)."""
        self._forked()
        old = self._jobs.pop(b, None)
        if old is not None:  # never taken (the queries moved elsewhere): let it finish before reusing buffers
            old[3].result()
        if self._ahead_pause[b]:
            self._ahead_pause[b] -= 1
            return
        if self._ahead_bufs is None:
            bands, slots, n = len(self.sizes), self.geometry.tiles.shape[2], self.n
            self._ahead_bufs = (np.empty((2, bands, slots, n, n), np.complex64),  # geometry tiles
                                np.empty((2, bands, 1, n, n), np.complex64),  # velocity tiles
                                np.zeros((bands, slots, n, n), np.complex64),  # the worker's spectra scratch
                                np.zeros((bands, 1, n, n), np.complex64))  # fmt: skip (zero: sparse bands)
        s = self._ahead_next[b]
        self._ahead_next[b] = 1 - s
        for key in [k for k, v in self._vel_made.items() if k[0] == b and v == s]:
            del self._vel_made[key]  # not taken by the velocity ring, about to be overwritten
        with_vel = self.velocity_ring.intervals[b] == self.geometry.intervals[b]
        self._jobs[b] = (t, s, with_vel, _AHEAD.start(self._make_ahead, b, t, s, with_vel), time.perf_counter(),
                         time.thread_time())  # fmt: skip

    def _make_ahead(self, b: int, t: float, s: int, with_vel: bool) -> tuple[float, float]:
        """(Worker thread.) `_geometry_snapshot`'s work into buffer set s: the same kernel and transforms. Returns
        the job's wall and thread CPU time (s): far apart, the worker shared a core (see `_fetch_ahead`)."""
        wall, cpu = time.perf_counter(), time.thread_time()
        self._make_snapshot_ahead(b, t, s, with_vel)
        return time.perf_counter() - wall, time.thread_time() - cpu

    def _make_snapshot_ahead(self, b: int, t: float, s: int, with_vel: bool) -> None:
        assert self._ahead_bufs is not None
        geo, vel, spec, vspec = self._ahead_bufs
        self._spectra(b, t, spec[b], vspec[b, : 1 if with_vel else 0])
        self._ifft2_into(spec[b], geo[s, b], b, True)
        if with_vel:
            self._ifft2_into(vspec[b], vel[s, b], b, True)

    AHEAD_PAUSE = 8  # intervals a band computes its snapshots here after the worker was late with one (then 16, …)
    AHEAD_PAUSE_MAX = 512

    def _fetch_ahead(self, b: int, t: float, out: np.ndarray) -> bool:
        """Copy band b's snapshot at t into out if it was made ahead (waiting for the worker if it is not done);
        False where it was not. A snapshot not ready in time, or one whose job took much more wall than CPU time
        (the worker shared a core: a loaded machine), pauses the band's work ahead for `AHEAD_PAUSE` intervals:
        without a core of its own the worker only adds its hand-offs. (Which path made a snapshot never changes its
        bytes.)"""
        self._forked()
        job = self._jobs.get(b)
        if job is None or job[0] != t:
            return False
        del self._jobs[b]
        ready = job[3].done()
        wall, cpu = job[3].result()  # re-raises the worker's error
        since, here = time.perf_counter() - job[4], time.thread_time() - job[5]
        # the worker descheduled for a third of its job, or this thread for a fifth of the time since it started it:
        # the two threads did not have two cores
        shared = wall > 1.5 * cpu + 50e-6 or here < 0.8 * since - 50e-6
        self.ahead_stats[0 if ready and not shared else 1] += 1
        if not ready or shared:  # pause, twice as long as last time while it lasts (a loaded machine stays loaded)
            self._ahead_backoff[b] = min(2 * self._ahead_backoff[b], self.AHEAD_PAUSE_MAX)
            self._ahead_pause[b] = self._ahead_backoff[b]
        else:  # in time on a core of its own: halve the next pause (a doubling is undone by one success only)
            self._ahead_backoff[b] = max(self._ahead_backoff[b] // 2, self.AHEAD_PAUSE // 2)
        assert self._ahead_bufs is not None
        out[:] = self._ahead_bufs[0][job[1], b]
        if job[2]:
            self._vel_made[(b, t)] = job[1]
        return True

    def _forked(self) -> None:
        """In a forked child, forget the parent's jobs: their worker thread did not come along."""
        if self._jobs_pid != os.getpid():
            self._jobs.clear()
            self._vel_made.clear()
            self._jobs_pid = os.getpid()

    def _drain(self) -> None:
        """Wait for the snapshots being made ahead (kept for `_fetch_ahead`): the worker and this thread share the
        phase tables."""
        self._forked()
        for job in self._jobs.values():
            job[3].result()

    def _geometry_snapshot(self, b: int, t: float, out: np.ndarray) -> None:
        """Band b's geometry tiles at t; where the velocity ring snapshots this band at the same times (usual for
        all but the longest band), its spectrum is made in the same pass and kept for `_kinematic_snapshot`."""
        if self._jobs:
            self._drain()
        slots = out.shape[0]
        with_vel = self.velocity_ring.intervals[b] == self.geometry.intervals[b]
        if self._pairs[b] is None:
            spec = self._spec[:slots]
            vel = np.empty((1 if with_vel else 0, self.n, self.n), np.complex64)
        else:  # kept zero outside the band's pairs; a velocity spectrum still waiting there is made again if asked
            if b not in self._sparse:
                self._sparse[b] = (np.zeros((slots, self.n, self.n), np.complex64),
                                   np.zeros((1, self.n, self.n), np.complex64))  # fmt: skip
            spec, vel = self._sparse[b][0], self._sparse[b][1][: 1 if with_vel else 0]
            for key in [k for k in self._vel_spectra if k[0] == b]:
                del self._vel_spectra[key]
        self._spectra(b, t, spec, vel)
        if with_vel:
            if len(self._vel_spectra) >= 4 * len(self.sizes):  # a ring's worth per band at most
                del self._vel_spectra[next(iter(self._vel_spectra))]
            self._vel_spectra[(b, t)] = vel
        self._ifft2_into(spec, out, b)

    def _ifft2_into(self, spec: np.ndarray, out: np.ndarray, b: int = -1, worker: bool = False) -> None:
        """out[:] = scipy.fft.ifft2(spec, norm="forward", workers=1) for spec and out (slots, N, N) complex64, out
        C-contiguous: the C++ transform that scipy.fft.ifft2 calls (pocketfft c2c over axes 1 and 2, inverse, no
        scaling, one thread) writing into out: the same bytes (tested) without a new array, a copy and the Python
        argument handling (which holds the GIL: a worker thread preempted there stalls the simulation thread).

        A sparse band's spectrum b (`_pairs`) is zero outside its columns [0, lo) and [hi, N): its transform along
        axis 1 (pocketfft's first) runs on those columns only, into an array kept zero between them, then along
        axis 2 as in the full transform: the same bytes (tested), 49 -> 34 µs at N = 128 in sea state 4. `worker`:
        the call is the worker thread's (its own intermediate arrays)."""
        if self._c2c is None or not out.flags.c_contiguous or spec.shape != out.shape:
            out[:] = self._ifft2(spec, norm="forward", workers=1)
            return
        cols = self._columns[b] if b >= 0 else None
        if cols is None:
            self._c2c(spec, (1, 2), False, 0, out, 1)
            return
        lo, hi = cols
        key = (worker, b, spec.shape[0])
        tmp = self._pruned.get(key)
        if tmp is None:
            tmp = self._pruned[key] = np.zeros(spec.shape, np.complex64)
        self._c2c(spec[:, :, :lo], (1,), False, 0, tmp[:, :, :lo], 1)
        if hi < self.n:
            self._c2c(spec[:, :, hi:], (1,), False, 0, tmp[:, :, hi:], 1)
        self._c2c(tmp, (2,), False, 0, out, 1)

    def _column_blocks(self, pairs: np.ndarray | None) -> tuple[int, int] | None:
        """(lo, hi): a sparse band's spectra are zero in the columns lo <= ix < hi (its pairs' columns and their
        mirrors lie outside); None for a dense band or where the blocks would cover half the columns or more."""
        if pairs is None:
            return None
        n = self.n
        cols = np.unique(np.concatenate([pairs[:, 1], (n - pairs[:, 1]) % n]))
        low, high = cols[cols < n // 2], cols[cols >= n // 2]
        lo = int(low.max()) + 1 if len(low) else 1
        hi = int(high.min()) if len(high) else n
        return (lo, hi) if lo + (n - hi) < n // 2 else None

    def _spectra(self, b: int, t: float, spec: np.ndarray, vel: np.ndarray) -> None:
        """Band b's geometry spectra (and velocity, if vel has a slot) at t: a sparse band (`_pairs`) writes its
        pairs only, into arrays kept zero elsewhere (the same bytes as the full pass)."""
        args = (self._amp[b], self._omega[b], self._khx[b], self._khy[b], t, spec.shape[0] > 1, spec, vel,
                *self._phases.at(b, t))  # fmt: skip
        pairs = self._pairs[b]
        if pairs is None:
            kern.geometry_and_velocity_spectra(*args)
        else:
            kern.geometry_and_velocity_spectra_at(pairs, *args)

    def _kinematic_snapshot(self, acceleration: bool, b: int, t: float, out: np.ndarray) -> None:
        made = None if acceleration else self._vel_made.pop((b, t), None)
        if made is not None:  # transformed ahead with the geometry (_make_ahead)
            assert self._ahead_bufs is not None
            out[:] = self._ahead_bufs[1][made, b]
            return
        spec = None if acceleration else self._vel_spectra.pop((b, t), None)
        if spec is None:
            spec = self._spec[: out.shape[0]]
            kern.kinematic_spectra(
                self._amp[b], self._omega[b], self._khx[b], self._khy[b], t, acceleration, spec
            )
        self._ifft2_into(spec, out, b)

    def node_cache(self) -> tuple[np.ndarray, np.ndarray, int]:
        """(cache, stamp, now) for the cached height kernels (`fft_kernels._corner`): blended heights of the tile
        nodes (bands, N, N) m, the blend state each holds, and the current state's number, which changes whenever
        the geometry blend (its weights, or a snapshot) changes. Call after `update`."""
        key = (self.geometry._key, self.geometry.transforms)
        if key != self._node_key:
            self._node_key, self._node_now = key, self._node_now + 1
        return self._node_heights, self._node_stamp, self._node_now

    def scratch(self, kind: str, n: int) -> np.ndarray:
        """A float64 scratch array kept between calls for n points: "bands" (n, bands), per-band heights of the
        cached kernels, or "coords" (3, n). (Made per call, a fleet's arrays would cost page faults every step.)
        Kept per (kind, n): a step asks for the hull's vertices and for the bodies' centres of mass (one array per
        kind made them both anew twice a step)."""
        array = self._scratch.get((kind, n))
        if array is None:
            if len(self._scratch) >= 8:  # callers of many sizes: start over
                self._scratch.clear()
            array = self._scratch[(kind, n)] = np.empty((n, len(self.sizes)) if kind == "bands" else (3, n))
        return array

    def update(self, t: float) -> np.ndarray:
        """Make the geometry snapshots around time t (s) present; returns the blend weights (ramp included)."""
        t = float(t)
        if t == self._updated[0] and self.geometry._key is self._updated[1]:  # this time's, not re-prepared since
            return self.geometry.weights
        weights = self.geometry.prepare(t, self.ramp(t))
        self._updated = (t, self.geometry._key)
        return weights

    def update_kinematics(self, t: float) -> None:
        """Make the velocity and acceleration snapshots around time t present (only `kinematics` needs them)."""
        self.velocity_ring.prepare(float(t), self.ramp(t))
        self.acceleration_ring.prepare(float(t), self.ramp(t))

    def tiles(self, t: float) -> np.ndarray:
        """Geometry tiles (bands, 4, N, N) at time t: h, Dx, Dy, w (unscaled by the ramp and choppiness)."""
        self.geometry.prepare(float(t), 1.0)
        g = np.einsum("br,brsyx->bsyx", self.geometry.weights, self.geometry.tiles)
        d = g[:, 1] if g.shape[1] > 1 else np.zeros_like(g[:, 0])
        return np.stack([g[:, 0].real, d.real, d.imag, g[:, 0].imag], axis=1)

    @overload
    def surface_labels(self, x, y, t: float, return_iterations: Literal[False] = False) -> Labels: ...
    @overload
    def surface_labels(self, x, y, t: float, return_iterations: Literal[True]) -> LabelsIterations: ...
    def surface_labels(self, x, y, t: float, return_iterations: bool = False) -> Labels | LabelsIterations:
        px, py = as_points(x, y)
        wts = self.update(t)
        x0, y0, z = np.empty_like(px), np.empty_like(px), np.empty_like(px)
        iters = np.empty(px.shape, dtype=np.int64)
        if self.choppiness == 0.0:  # labels are the points: exactly the inversion's first (and last) iterate
            kernel = pick(kern.HEIGHTS, len(px))
            if kernel is kern.HEIGHTS[0]:  # serial: blended tile nodes once per blend state
                band_h = np.empty((len(px), len(self.sizes)))
                kern.heights_cached(px, py, self.geometry.tiles, wts, self.inv_cells, z, band_h, *self.node_cache())
            else:
                kernel(px, py, self.geometry.tiles, wts, self.inv_cells, z)
            x0[:], y0[:], iters[:] = px, py, 0
            return (x0, y0, z, iters) if return_iterations else (x0, y0, z)
        args = (self.geometry.tiles, wts, self.inv_cells, self.choppiness, self.tol, self.max_iter)
        pick(kern.INVERT, len(px))(px, py, *args, x0, y0, z, iters)
        return (x0, y0, z, iters) if return_iterations else (x0, y0, z)

    def height_kernel_args(self, t: float, n: int) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray],
                                                            tuple[np.ndarray, np.ndarray, np.ndarray, int]] | None:
        """What follows the points and precedes `z_out` ... in `fft_kernels.heights_cached` for n points at time t:
        (tiles, weights, inv_cells), then (band scratch, node cache, stamps, state) -- the kernel `elevation` uses
        when a sea without displacement is answered serially; None otherwise."""
        if self.choppiness != 0.0 or pick(kern.HEIGHTS, n) is not kern.HEIGHTS[0]:
            return None
        return (self.geometry.tiles, self.update(t), self.inv_cells), (self.scratch("bands", n), *self.node_cache())

    def _surface(self, x0, y0, t):
        x0, y0 = as_points(x0, y0)
        wts = self.update(t)
        out, normals = np.empty((len(x0), 3)), np.empty((len(x0), 3))
        pick(kern.SURFACE_POINTS, len(x0))(x0, y0, self.geometry.tiles, wts, self.inv_cells, self.choppiness,
                                           out, normals)  # fmt: skip
        return out, normals

    def displaced_surface(self, x0, y0, t: float) -> np.ndarray:
        return self._surface(x0, y0, t)[0]

    def normal(self, x, y, t: float) -> np.ndarray:
        """Unit normal (n, 3), ENU, of the interpolated surface at world points (x, y)."""
        x0, y0, _ = self.surface_labels(x, y, t)
        return self._surface(x0, y0, t)[1]

    def kinematics(self, x, y, z, t: float, acceleration: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """Orbital velocity and acceleration (n, 3), ENU, at world points; linear (Airy) deep-water kinematics.

        Exact at the surface; below it each band decays as exp(κ_b z') with its velocity-weighted mean
        wavenumber κ_b (an approximation within a band), z' = min(z - η, 0) (Wheeler stretching, deep water).
        Without `acceleration` the acceleration tiles are not transformed and the second array has no rows.
        """
        px, py, pz = as_points(x, y, z)
        x0, y0, eta = self.surface_labels(px, py, t)
        s = self.ramp(t)
        vel_ring, acc_ring = self.velocity_ring, self.acceleration_ring
        vel_ring.prepare(float(t), s)
        if acceleration:
            acc_ring.prepare(float(t), s)
        zeff = np.minimum(pz - eta, 0.0)
        vel, acc = np.empty((len(px), 3)), np.empty((len(px) if acceleration else 0, 3))
        pick(kern.SAMPLE_KINEMATICS, len(x0))(x0, y0, zeff, self.geometry.tiles, self.geometry.weights,
                                              vel_ring.tiles, vel_ring.weights, acc_ring.tiles, acc_ring.weights,
                                              self.inv_cells, self.decay_k, vel, acc)  # fmt: skip
        return vel, acc

    def velocity(self, x, y, z, t: float) -> np.ndarray:
        if self.choppiness == 0.0:  # labels = points: heights and velocities in one compiled call
            px, py, pz = as_points(x, y, z)
            if pick(kern.SAMPLE_KINEMATICS, len(px)) is kern.SAMPLE_KINEMATICS[0]:
                wts = self.update(t)
                ring = self.velocity_ring
                ring.prepare(float(t), self.ramp(t))
                vel = np.empty((len(px), 3))
                kern.velocity_cached(px, py, pz, self.geometry.tiles, wts, ring.tiles, ring.weights,
                                     self.acceleration_ring.tiles, self.acceleration_ring.weights, self.inv_cells,
                                     self.decay_k, self.scratch("bands", len(px)), *self.node_cache(), vel)  # fmt: skip
                return vel
        return self.kinematics(x, y, z, t, acceleration=False)[0]

    def velocity_at_points(self, points: np.ndarray, level: float, t: float, current: np.ndarray, out: np.ndarray
                           ) -> bool:  # fmt: skip
        """Ocean.velocity's rows for points (n,3) m world (z relative to `level`) plus a uniform current (3,) m/s,
        written into out (n,3) in one compiled call; False (nothing done) where that path does not apply."""
        n = len(points)
        if self.choppiness != 0.0 or pick(kern.SAMPLE_KINEMATICS, n) is not kern.SAMPLE_KINEMATICS[0]:
            return False
        wts = self.update(t)
        ring = self.velocity_ring
        ring.prepare(float(t), self.ramp(t))
        kern.velocity_cached_points(points, float(level), self.geometry.tiles, wts, ring.tiles, ring.weights,
                                    self.acceleration_ring.tiles, self.acceleration_ring.weights, self.inv_cells,
                                    self.decay_k, self.scratch("bands", n), self.scratch("coords", n),
                                    *self.node_cache(), current, out)  # fmt: skip
        return True

    def acceleration(self, x, y, z, t: float) -> np.ndarray:
        return self.kinematics(x, y, z, t)[1]

    def held_variance(self) -> float:
        """The elevation variance (m²) the spectrum puts in this field's bins (the bins' amplification for bilinear
        interpolation taken out): below the spectrum's m0 where waves are longer than the largest tile or
        shorter than the smallest tile's cells allow."""
        h = (self.sizes / self.n)[:, None, None]
        gain = _bilinear_gain(self._kx * h) * _bilinear_gain(self._ky * h)
        return float(np.sum(0.5 * np.abs(self._amp) ** 2 * gain))

    def components(self, min_amplitude: float = 0.0) -> WaveComponents:
        """Every owned bin as a travelling component (same sea as the tiles, without interpolation)."""
        keep = np.abs(self._amp) > min_amplitude
        return WaveComponents(
            amplitude=np.abs(self._amp[keep]),
            kx=self._kx[keep],
            ky=self._ky[keep],
            omega=self._omega[keep],
            phase=np.angle(self._amp[keep]),
            steepness=np.full(int(keep.sum()), self.choppiness),
        )
