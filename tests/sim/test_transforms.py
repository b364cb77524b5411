"""core/transforms.py helpers against numpy and closed forms."""

import numpy as np

from usvsim.core.transforms import cross3, matrix_from_quat


def test_cross3_equals_numpy_bit_for_bit():
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=3) * 1e3, rng.normal(size=3) * 1e-3
    assert np.array_equal(cross3(a, b), np.cross(a, b))
    rows, one = rng.normal(size=(50, 3)), rng.normal(size=3)
    assert np.array_equal(cross3(rows, one), np.cross(rows, one))  # rows with one vector (broadcast)
    assert np.array_equal(cross3(one, rows), np.cross(one, rows))
    assert np.array_equal(cross3(rows, rows[::-1]), np.cross(rows, rows[::-1]))
    stacked = rng.normal(size=(4, 5, 3))
    assert np.array_equal(cross3(stacked, stacked[:, ::-1]), np.cross(stacked, stacked[:, ::-1]))


def test_cross3_right_handed_basis():
    x, y, z = np.eye(3)
    assert np.array_equal(cross3(x, y), z) and np.array_equal(cross3(y, z), x) and np.array_equal(cross3(z, x), y)
    assert cross3(x, [0.0, 2.0, 0.0]).tolist() == [0.0, 0.0, 2.0]  # a list as the second vector


def test_matrix_from_quat_one_equals_batched_bit_for_bit():
    rng = np.random.default_rng(5)
    quats = rng.normal(size=(64, 4)) * 3.0  # not unit: both normalize
    batched = matrix_from_quat(quats)
    for q, m in zip(quats, batched, strict=True):
        assert np.array_equal(matrix_from_quat(q), m)
    r = matrix_from_quat(quats[0])
    assert np.allclose(r @ r.T, np.eye(3), atol=1e-14) and np.isclose(np.linalg.det(r), 1.0)
    assert np.allclose(matrix_from_quat([np.cos(0.5), 0.0, 0.0, np.sin(0.5)]),
                       [[np.cos(1.0), -np.sin(1.0), 0.0], [np.sin(1.0), np.cos(1.0), 0.0], [0.0, 0.0, 1.0]])  # fmt: skip
