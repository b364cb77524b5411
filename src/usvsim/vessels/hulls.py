"""Procedural hull meshes: closed lofts of superellipse cross-sections along the body x axis."""

from __future__ import annotations

import numpy as np

from usvsim.vessels.parts import Mesh


def loft(x, z_bottom, z_top, half_width, y_center=0.0, n_around=16, exponent=2.0) -> Mesh:
    """Closed watertight hull from stations along x (FLU, m), each a superellipse section.

    Station i spans z_bottom[i]..z_top[i] vertically and ±half_width[i] about `y_center`; `exponent`
    2 gives ellipses, larger values boxier sections. The two ends are closed by fans.
    """
    x, zb, zt, hw = (np.asarray(a, dtype=float) for a in (x, z_bottom, z_top, half_width))
    theta = np.linspace(0.0, 2 * np.pi, n_around, endpoint=False)
    c, s = np.cos(theta), np.sin(theta)
    p = 2.0 / exponent
    cy, sz = np.sign(c) * np.abs(c) ** p, np.sign(s) * np.abs(s) ** p
    zc, hh = (zb + zt) / 2, (zt - zb) / 2
    rings = np.empty((len(x), n_around, 3))
    rings[..., 0] = x[:, None]
    rings[..., 1] = y_center + hw[:, None] * cy[None, :]
    rings[..., 2] = zc[:, None] + hh[:, None] * sz[None, :]
    verts = np.vstack([rings.reshape(-1, 3), [[x[0], y_center, zc[0]], [x[-1], y_center, zc[-1]]]])
    faces = []
    n = n_around
    for i in range(len(x) - 1):
        for j in range(n):
            a, b = i * n + j, i * n + (j + 1) % n
            c2, d = a + n, b + n
            faces += [(a, c2, b), (b, c2, d)]
    start, end = len(x) * n, len(x) * n + 1
    last = (len(x) - 1) * n
    for j in range(n):
        faces.append((start, j, (j + 1) % n))
        faces.append((end, last + (j + 1) % n, last + j))
    mesh = Mesh(verts, np.array(faces))
    if mesh.volume() < 0:
        mesh = Mesh(mesh.vertices, mesh.faces[:, ::-1])
    return mesh
