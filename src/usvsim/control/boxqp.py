"""Small dense box-constrained QP, solved exactly by a primal active-set method (numba).

    minimize ½ zᵀ H z - gᵀ z   subject to   lo ≤ z ≤ hi,   H symmetric positive definite, n ≲ 20.

From a feasible point, each iteration solves the equality-constrained problem on the free variables
(Cholesky of the free block); if that point is feasible the bound multipliers are checked and the most
violated bound is released, else the step is cut at the first bound reached, which becomes active.
The cost decreases strictly, so the method ends in finitely many iterations (capped at 5n + 10).
Allocation problems have n = number of thrusters, so one solve costs a few microseconds.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def _solve_free(H, g, z, free, nf, idx, A, b):
    """Minimizer over the free variables with the others fixed: H_FF z_F = g_F - H_FA z_A (Cholesky)."""
    n = z.shape[0]
    k = 0
    for i in range(n):
        if free[i]:
            idx[k] = i
            k += 1
    for a in range(nf):
        i = idx[a]
        r = g[i]
        for j in range(n):
            if not free[j]:
                r -= H[i, j] * z[j]
        b[a] = r
        for c in range(nf):
            A[a, c] = H[i, idx[c]]
    for a in range(nf):  # in-place Cholesky, lower triangle
        s = A[a, a]
        for c in range(a):
            s -= A[a, c] * A[a, c]
        A[a, a] = np.sqrt(max(s, 1e-300))
        for r in range(a + 1, nf):
            s = A[r, a]
            for c in range(a):
                s -= A[r, c] * A[a, c]
            A[r, a] = s / A[a, a]
    for a in range(nf):  # forward then backward substitution
        s = b[a]
        for c in range(a):
            s -= A[a, c] * b[c]
        b[a] = s / A[a, a]
    for a in range(nf - 1, -1, -1):
        s = b[a]
        for c in range(a + 1, nf):
            s -= A[c, a] * b[c]
        b[a] = s / A[a, a]


@njit(cache=True)
def _release(H, g, z, state):
    """Index of the active bound with the most negative multiplier, or -1 if all are optimal."""
    n = z.shape[0]
    worst, best = -1, 1e-12
    for i in range(n):
        if state[i] == 0:
            continue
        grad = -g[i]
        for j in range(n):
            grad += H[i, j] * z[j]
        violation = -grad if state[i] < 0 else grad  # at lo the gradient must be >= 0, at hi <= 0
        if violation > best:
            worst, best = i, violation
    return worst


@njit(cache=True)
def box_qp(H, g, lo, hi, z):
    """Solve in place: z holds the start (clipped into the box) and returns the minimizer.
    Returns the number of iterations used."""
    n = z.shape[0]
    state = np.zeros(n, dtype=np.int64)  # -1 at lo, +1 at hi, 0 free
    free = np.ones(n, dtype=np.bool_)
    idx = np.empty(n, dtype=np.int64)
    A, b = np.empty((n, n)), np.empty(n)
    for i in range(n):
        z[i] = min(max(z[i], lo[i]), hi[i])
        if lo[i] == hi[i]:
            state[i], free[i] = -1, False
    for it in range(5 * n + 10):
        nf = 0
        for i in range(n):
            nf += free[i]
        if nf > 0:
            _solve_free(H, g, z, free, nf, idx, A, b)
        t, block, side = 1.0, -1, 0
        for a in range(nf):
            i, d = idx[a], b[a] - z[idx[a]]
            if d < 0.0 and z[i] + t * d < lo[i]:
                t, block, side = (lo[i] - z[i]) / d, i, -1
            elif d > 0.0 and z[i] + t * d > hi[i]:
                t, block, side = (hi[i] - z[i]) / d, i, 1
        for a in range(nf):
            z[idx[a]] += t * (b[a] - z[idx[a]])
        if block >= 0:
            z[block] = lo[block] if side < 0 else hi[block]
            state[block], free[block] = side, False
            continue
        j = _release(H, g, z, state)
        if j < 0:
            return it + 1
        state[j], free[j] = 0, True
    return 5 * n + 10
