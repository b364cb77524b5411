"""FFT snapshots blended in time: the error bound holds against exact transforms, results do not depend on
the query history, silent bands are never transformed."""

import math

import numpy as np
import pytest

from usvsim.ocean import spectra
from usvsim.ocean.fft import FFTWaveField, cascade_sizes, directional_spectrum, pair_bins
from usvsim.ocean.fft_time import (
    SNAPSHOTS,
    SNAPSHOTS_CHOPPY,
    _blend_weights,
    _denominators,
    error_factor,
    lagrange_weights,
    nodes_of,
)

JONSWAP = directional_spectrum(lambda w: spectra.jonswap(w, 1.88, 8.8, 2.0), 0.3, 10.0)
SIZES = cascade_sizes(2 * math.pi * spectra.G / (2 * math.pi / 8.8) ** 2, 3, 64)


def field(tolerance, seed=4, choppiness=0.0):
    return FFTWaveField(JONSWAP, SIZES, np.random.default_rng(seed), 64, choppiness, time_tolerance=tolerance)


@pytest.mark.parametrize("snapshots", [4, 6, 8])
def test_error_factor_is_the_lagrange_remainder(snapshots):
    """|R(u)| ≤ x^K/K! · |Π (u - x_i)| (Hermite–Genocchi: |d^K/du^K e^{-ixu}| = x^K), reached as x → 0."""
    nodes = nodes_of(snapshots)
    np.testing.assert_array_equal(nodes, np.arange(1 - snapshots // 2, snapshots // 2 + 1))
    u = np.linspace(0.0, 1.0, 2001)
    node_poly = np.abs(np.prod(u[:, None] - nodes[None, :], axis=1)).max() / math.factorial(snapshots)
    if snapshots == 4:
        assert node_poly == pytest.approx(0.5625 / 24)  # max |(u+1)u(u-1)(u-2)| at u = 1/2
    x = np.array([0.05, 0.2, 0.4])
    eps = error_factor(x, nodes)
    assert np.all(eps <= node_poly * x**snapshots * 1.001)
    assert np.all(eps >= node_poly * x**snapshots * 0.9)
    k = len(nodes)
    at_nodes = lagrange_weights(np.array([0.0, 1.0]), nodes)  # u = 0, 1: the snapshots m and m + 1 alone
    np.testing.assert_array_equal(at_nodes, np.eye(k)[[k // 2 - 1, k // 2]])
    np.testing.assert_allclose(lagrange_weights(u, nodes).sum(axis=1), 1.0, atol=1e-13)


def test_blend_weights_are_lagrange_weights_in_the_ring_order():
    """The compiled weights equal `lagrange_weights` bit for bit, node i in ring entry (m + nodes[0] + i) mod K."""
    nodes = nodes_of(SNAPSHOTS)
    k = len(nodes)
    intervals = np.array([0.3, 0.07, math.inf, 0.0])
    weights, m_out = np.zeros((4, k)), np.zeros(4, np.int64)
    for t in (0.0, 0.01, 0.29, 0.3, 1.234, 17.5):
        _blend_weights(t, 0.75, intervals, np.zeros(4, np.int64), nodes, _denominators(nodes), weights, m_out)
        for b in range(2):
            m = math.floor(t / intervals[b])
            assert m_out[b] == m
            expected = 0.75 * lagrange_weights(t / intervals[b] - m, nodes)
            ring = [(m + int(nodes[0]) + i) % k for i in range(k)]
            np.testing.assert_array_equal(weights[b, ring], expected)


@pytest.mark.parametrize("choppiness", [0.0, 0.7])
def test_interpolated_field_is_within_its_bound_of_the_exact_one(choppiness):
    """Eight snapshots per query without displacement, four in a choppy sea (its queries blend per point)."""
    fast, exact = field(2e-3, choppiness=choppiness), field(0.0, choppiness=choppiness)
    snapshots = SNAPSHOTS if choppiness == 0.0 else SNAPSHOTS_CHOPPY
    for ring in (fast.geometry, fast.velocity_ring, fast.acceleration_ring):
        assert ring.weights.shape[1] == ring.tiles.shape[1] == len(ring.nodes) == snapshots
    assert all(0.05 < d < 2.0 for d in fast.snapshot_intervals_s["geometry"])
    rng = np.random.default_rng(0)
    x, y = rng.uniform(0, 500, 3000), rng.uniform(0, 500, 3000)
    z = np.full(3000, 3.0)  # above the surface: surface kinematics
    comps = exact.components()
    sigma = [math.sqrt(np.sum(0.5 * comps.amplitude**2 * comps.omega ** (2 * p))) for p in range(3)]
    for t in (3.217, 7.5, 12.0031):
        eta = fast.elevation(x, y, t) - exact.elevation(x, y, t)
        v_fast, a_fast = fast.kinematics(x, y, z, t)
        v_exact, a_exact = exact.kinematics(x, y, z, t)
        assert np.sqrt(np.mean(eta**2)) <= 2e-3 * sigma[0]
        assert np.sqrt(np.mean((v_fast - v_exact)[:, 2] ** 2)) <= 2e-3 * sigma[1]
        assert np.sqrt(np.mean((a_fast - a_exact)[:, 2] ** 2)) <= 2e-3 * sigma[2]


def test_a_time_gives_the_same_sea_whatever_was_queried_before():
    a, b = field(1e-3), field(1e-3)
    x = np.linspace(0, 80, 200)
    for t in np.arange(0.0, 3.0, 0.01):  # a stepped run
        a.elevation(x, x, t)
    b.elevation(x, x, 50.0)  # another history
    t = 3.0
    np.testing.assert_array_equal(a.elevation(x, x, t), b.elevation(x, x, t))
    np.testing.assert_array_equal(a.velocity(x, x, x * 0, t), b.velocity(x, x, x * 0, t))


def test_transforms_are_amortized_and_silent_bands_skipped():
    def two_bands(kx, ky, band):
        return JONSWAP(kx, ky, band) if band == 0 else np.zeros_like(kx)

    f = FFTWaveField(two_bands, SIZES[:2], np.random.default_rng(1), 64)
    assert math.isinf(f.snapshot_intervals_s["geometry"][1])
    x = np.zeros(4)
    for t in np.arange(0.0, 10.0, 0.01):
        f.elevation(x, x, t)
    assert f.geometry.transforms <= SNAPSHOTS + 10.0 / f.snapshot_intervals_s["geometry"][0] + 1
    assert f.velocity_ring.transforms == f.acceleration_ring.transforms == 0


@pytest.mark.parametrize("tolerance", [0.0, 1e-3])
def test_ramp_scales_every_snapshot(tolerance):
    f = FFTWaveField(JONSWAP, SIZES, np.random.default_rng(2), 64, ramp_time_s=5.0, time_tolerance=tolerance)
    g = FFTWaveField(JONSWAP, SIZES, np.random.default_rng(2), 64, time_tolerance=tolerance)
    x = np.linspace(0, 50, 20)
    np.testing.assert_allclose(
        f.elevation(x, x, 2.0), (1 - math.exp(-0.4)) * g.elevation(x, x, 2.0), atol=1e-12
    )


def test_phase_tables_give_the_snapshot_rotations_and_spectra():
    """A snapshot's e^{-iωt} from the tables (fft.PhaseTables) equals the direct one within 1e-14 for times on the
    band's grid (negative m, every r, q boundaries, revisits), and the spectra made with it equal the
    sine/cosine ones to complex64 rounding; off-grid times fall back to the sine and cosine."""
    from usvsim.ocean import fft_kernels as kern

    f = field(1e-3)
    for b, dt in enumerate(f.geometry.intervals):
        w = f._omega[b]
        for m in (-1, 0, 1, 7, 8, 9, 23, 3, 1000, 4):
            t = m * dt
            phases, bits = f._phases.at(b, t)
            rot = phases[0] * (phases[1] if bits & 1 else 1) * (phases[2] if bits & 2 else 1)
            rot = rot * (phases[3] if bits & 4 else 1)
            assert bits == m % 8
            used = pair_bins(f._amp)[b]  # the bins the kernel reads (the tables leave the others at 0)
            assert used.sum() <= f.n * f.n // 2 + 2 and not rot[~used].any()
            err = np.abs(rot - np.exp(-1j * w * t))[used].max()
            assert err <= 1e-14 * max(1.0, float(np.abs(w * t).max()))
            spec, ref = np.zeros((1, f.n, f.n), np.complex64), np.zeros((1, f.n, f.n), np.complex64)
            vel, vref = np.zeros_like(spec), np.zeros_like(spec)
            args = (f._amp[b], w, f._khx[b], f._khy[b], t, False)
            kern.geometry_and_velocity_spectra(*args, spec, vel, phases, bits)
            kern.geometry_and_velocity_spectra(*args, ref, vref, phases, -1)
            scale = float(np.abs(ref).max())
            assert np.abs(spec - ref).max() <= 1e-6 * scale and np.abs(vel - vref).max() <= 1e-6 * float(np.abs(vref).max())
        assert f._phases.at(b, 0.5 * dt)[1] == -1


def test_snapshots_made_ahead_on_the_worker_are_the_same_bytes(monkeypatch):
    """A stepped run whose next snapshots are made on the worker thread (FFTWaveField.AHEAD) gives the bytes of one
    that makes every snapshot when it is needed, whether the worker was in time or not (a slow worker is waited
    for, then its band pauses), and after jumps in time."""
    import time

    monkeypatch.setattr(FFTWaveField, "AHEAD", False)
    here = field(1e-3)
    monkeypatch.setattr(FFTWaveField, "AHEAD", True)
    monkeypatch.setattr(FFTWaveField, "AHEAD_PAUSE", 2)  # late jobs pause their band briefly: jobs keep coming
    monkeypatch.setattr(FFTWaveField, "AHEAD_PAUSE_MAX", 2)
    ahead = field(1e-3)
    if ahead.geometry.ahead is None:
        pytest.skip("one core: nothing is made ahead")
    make = ahead._make_ahead

    def slow(*args):  # every third job late: the main thread waits for it
        slow.calls += 1
        if slow.calls % 3 == 0:
            time.sleep(0.002)
        return make(*args)

    slow.calls = 0
    monkeypatch.setattr(ahead, "_make_ahead", slow)
    x = np.linspace(0.0, 60.0, 50)
    times = list(np.arange(0.0, 20.0, 0.01)) + [30.0, 1.5] + list(1.5 + np.arange(1, 100) * 0.01)
    for t in times:
        np.testing.assert_array_equal(ahead.elevation(x, x, t), here.elevation(x, x, t))
        np.testing.assert_array_equal(ahead.velocity(x, x, -x / 60, t), here.velocity(x, x, -x / 60, t))
    assert slow.calls > 10 and sum(ahead.ahead_stats) > 10
    assert ahead.geometry.transforms == here.geometry.transforms


@pytest.mark.skipif(not hasattr(__import__("os"), "fork"), reason="needs fork")
def test_a_forked_child_does_not_wait_for_the_parents_worker(monkeypatch):
    """A field forked while a snapshot job is pending (batch/runner.py forks warm processes) makes the snapshot
    itself: the job's thread did not come along, so waiting for it would never end."""
    import os
    import signal
    import threading

    monkeypatch.setattr(FFTWaveField, "AHEAD", True)
    f, ref = field(1e-3), field(1e-3)
    if f.geometry.ahead is None:
        pytest.skip("one core: nothing is made ahead")
    make, gate = f._make_ahead, threading.Event()
    f._make_ahead = lambda *args: gate.wait() and make(*args)
    x = np.linspace(0.0, 60.0, 20)
    for t in np.arange(0.0, 1.0, 0.01):
        f.elevation(x, x, t)
        if f._jobs:
            break
    assert f._jobs  # a job is pending on the worker (held at the gate)
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: a stepped run on, compared with a field that never forked
        try:
            signal.alarm(30)  # a hang ends the child (and fails the test) instead of the session
            f._make_ahead = make  # the child's own jobs run (its gate is never opened)
            ok = all(np.array_equal(f.elevation(x, x, t), ref.elevation(x, x, t)) for t in np.arange(0.0, 3.0, 0.01))
            os.write(w, b"1" if ok else b"0")
        finally:
            os._exit(0)
    os.close(w)
    gate.set()
    os.waitpid(pid, 0)
    assert os.read(r, 1) == b"1"


@pytest.mark.parametrize("choppy", [False, True])
def test_sparse_bands_make_the_same_spectra_pair_by_pair(choppy):
    """The long bands of a cascade have an amplitude in few bins: their spectra are made over those pairs only
    (fft_kernels.geometry_and_velocity_spectra_at) into arrays kept zero elsewhere: the same bytes as the full pass,
    on and off the phase tables' grid."""
    from usvsim.ocean import fft_kernels as kern

    f = field(1e-3)
    used = pair_bins(f._amp)
    assert f._pairs[0] is not None and f._pairs[-1] is None  # SIZES at 64: the longest band sparse, the finest not
    for b in range(len(f.sizes)):
        pairs = np.argwhere(used[b])
        full = [np.zeros((2, f.n, f.n), np.complex64), np.zeros((1, f.n, f.n), np.complex64)]
        part = [np.zeros_like(full[0]), np.zeros_like(full[1])]
        for t in (0.0, 3 * f.geometry.intervals[b], 17 * f.geometry.intervals[b], 2.345):
            args = (f._amp[b], f._omega[b], f._khx[b], f._khy[b], t, choppy)
            phases = f._phases.at(b, t)
            kern.geometry_and_velocity_spectra(*args, full[0][: 1 + choppy], full[1], *phases)
            kern.geometry_and_velocity_spectra_at(pairs, *args, part[0][: 1 + choppy], part[1], *phases)
            assert full[0].tobytes() == part[0].tobytes() and full[1].tobytes() == part[1].tobytes()


def test_snapshot_transforms_into_the_ring_are_scipys_ifft2():
    """FFTWaveField._ifft2_into (scipy's pocketfft transform writing into the ring) gives scipy.fft.ifft2's bytes."""
    import scipy.fft

    f = field(1e-3)
    rng = np.random.default_rng(3)
    spec = (rng.standard_normal((2, f.n, f.n)) + 1j * rng.standard_normal((2, f.n, f.n))).astype(np.complex64)
    out = np.zeros((3, 2, f.n, f.n), np.complex64)[1]
    f._ifft2_into(spec, out)
    assert f._c2c is not None  # the fast path is what runs here
    assert out.tobytes() == scipy.fft.ifft2(spec, norm="forward", workers=1).tobytes()
    # a sparse band's spectra (zero between its column blocks) transformed over those columns first
    b = 0
    assert f._columns[b] is not None
    for worker in (False, True):
        for t in (0.0, 5 * f.geometry.intervals[b]):
            band = np.zeros((2, f.n, f.n), np.complex64)
            f._spectra(b, t, band[:1], band[1:])
            f._ifft2_into(band, out, b, worker)
            assert out.tobytes() == scipy.fft.ifft2(band, norm="forward", workers=1).tobytes()


def test_without_the_private_pocketfft_transform_the_sea_is_the_same():
    """scipy's private pocketfft module may change in any release: `pocketfft_c2c` checks it once and the field
    falls back to scipy.fft.ifft2 (plus a copy), with the same heights to the bit."""
    from usvsim.ocean.fft import pocketfft_c2c

    assert pocketfft_c2c() is not None  # this scipy has it and it passed the check
    fast, slow = field(1e-3), field(1e-3)
    slow._c2c = None
    px, py = np.linspace(0.0, 150.0, 400), np.linspace(-30.0, 60.0, 400)
    for t in (0.0, 3.3, 17.0):
        assert fast.elevation(px, py, t).tobytes() == slow.elevation(px, py, t).tobytes()
